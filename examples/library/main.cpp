// s3m as a library: the loop a robot's own program runs. Frames come from a TUM-layout folder
// here; a camera driver fills s3m::RgbdFrame the same way (colour BGR8, depth in metres as CV_32F,
// timestamp in seconds, index counting from 0) and calls Pipeline::process() as frames arrive.
//
//   s3m_library_example DATASET [PRESET.yaml]
//
// Prints one line per keyframe (pose in the world frame, metres) and, at the end, how many frames
// were tracked and the semantic map's voxels per class; writes the map to example_map.ot in the
// working folder.
#include <cstdio>
#include <exception>
#include <memory>
#include <string>

#include "s3m/core/classes.hpp"
#include "s3m/mapping/map_io.hpp"
#include "s3m/mapping/queries.hpp"
#include "s3m/pipeline/factories.hpp"
#include "s3m/pipeline/frame_source.hpp"
#include "s3m/pipeline/map_integrator.hpp"
#include "s3m/pipeline/pipeline.hpp"
#include "s3m/pipeline/unregistered_depth.hpp"

namespace {

int run(const std::string& dataset, const std::string& preset) {
  namespace p = s3m::pipeline;
  // 1. Settings: a preset (config/*.yaml, documented in config/README.md) or the defaults.
  p::PipelineConfig config = preset.empty() ? p::PipelineConfig{} : p::load_pipeline_config(preset);
  config.validate();
  // 2. Frames and the camera that took them.
  const std::unique_ptr<p::FrameSource> source = p::open_tum_source(dataset, config.dataset);
  const s3m::PinholeCamera& camera = source->camera();
  std::printf("depth %s\n", p::resolve_depth_registration(config, *source).c_str());
  // 3. The three components: SLAM poses, a segmenter (the oracle on simulator output, else the
  //    shipped real-image model), the semantic map.
  auto poses = p::make_slam_poses(camera, config);
  const p::SegmenterChoice choice =
      p::choose_segmenter({}, config, p::simulator_sign(dataset, source->has_labels()));
  auto segmenter = p::make_segmenter(choice, config, source->has_labels());
  std::printf("segmenter %s (%s)\n", choice.type.c_str(), choice.reason.c_str());
  auto map = std::make_unique<p::MapIntegrator>(config.map);
  p::Pipeline pipeline(config, camera, std::move(poses), std::move(segmenter), std::move(map));
  // 4. Live output: called for every frame once it went through all five steps.
  pipeline.set_frame_listener(
      [](const p::FrameOutcome& f, const s3m::RgbdFrame&, const s3m::semantics::LabelMap&) {
        if (!f.keyframe) return;
        const Eigen::Vector3d t = f.T_w_c.translation();
        std::printf("keyframe at frame %d: camera at (%.3f, %.3f, %.3f) m, %s\n", f.index, t.x(), t.y(),
                    t.z(), s3m::to_string(f.state));
      });
  for (std::size_t i = 0; i < source->size(); ++i) pipeline.process(source->load(i));
  pipeline.finish();
  // 5. Results: frames tracked, the map and what it holds (pipeline.poses() has the trajectory).
  const auto& c = pipeline.counters();
  std::printf("frames %zu tracked %zu keyframes %zu integrated %zu\n", c.frames, c.tracked, c.keyframes,
              c.integrated);
  const s3m::mapping::SemanticOcTree& tree = pipeline.map()->tree();
  std::printf("map: %zu occupied voxels of %.2f m\n", pipeline.map()->occupied_voxels(),
              pipeline.map()->resolution_m());
  const std::vector<std::size_t> counts = s3m::mapping::class_voxel_counts(tree);
  for (std::size_t id = 0; id < counts.size(); ++id)
    if (counts[id] > 0)
      std::printf("  %-10s %zu voxels\n", tree.classes().at(s3m::ClassId(id)).name.c_str(), counts[id]);
  s3m::mapping::save_semantic_map(tree, "example_map.ot");
  std::printf("wrote example_map.ot (s3m view example_map.ot --out viewer/ shows it)\n");
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  if (argc < 2 || argc > 3) {
    std::fprintf(stderr, "usage: %s DATASET [PRESET.yaml]\n", argv[0]);
    return 2;
  }
  try {
    return run(argv[1], argc == 3 ? argv[2] : "");
  } catch (const std::exception& e) {  // s3m::Error says which file and what was expected
    std::fprintf(stderr, "error: %s\n", e.what());
    return 1;
  }
}
