#include "s3m/run/dataset_check.hpp"

#include <algorithm>
#include <cmath>
#include <sstream>

#include <fmt/format.h>

#include "s3m/io/association.hpp"
#include "s3m/io/trajectory.hpp"
#include "s3m/pipeline/factories.hpp"
#include "s3m/pipeline/frame_source.hpp"
#include "s3m/pipeline/unregistered_depth.hpp"
#include "s3m/run/effective_config.hpp"
#include "s3m/run/run.hpp"

namespace s3m::run {
namespace {

void timing(const pipeline::FrameSource& source, DatasetCheck& c) {
  c.frames = source.size();
  if (c.frames == 0) return;
  c.t_first_s = source.timestamp(0);
  c.t_last_s = source.timestamp(c.frames - 1);
  std::vector<double> steps;
  for (std::size_t i = 1; i < c.frames; ++i) {
    const double step = source.timestamp(i) - source.timestamp(i - 1);
    steps.push_back(step);
    if (step > c.largest_gap_s) c.largest_gap_s = step, c.largest_gap_after = i - 1;
  }
  if (steps.empty()) return;
  std::nth_element(steps.begin(), steps.begin() + steps.size() / 2, steps.end());
  c.median_step_s = steps[steps.size() / 2];
}

void ground_truth(const pipeline::FrameSource& source, double max_dt_s, DatasetCheck& c) {
  const io::Trajectory& gt = source.groundtruth();
  c.gt_poses = gt.size();
  for (std::size_t i = 1; i < gt.size(); ++i)
    c.gt_path_m += (gt[i].T_w_x.translation() - gt[i - 1].T_w_x.translation()).norm();
  if (gt.empty()) return;
  // As TumDataset::groundtruth_at: the nearest pose, within max_dt_s.
  const std::vector<double> times = io::timestamps(gt);
  for (std::size_t i = 0; i < source.size(); ++i) {
    const double t = source.timestamp(i);
    c.frames_with_gt += std::abs(times[io::closest_index(times, t)] - t) <= max_dt_s;
  }
}

}  // namespace

DatasetCheck check_dataset(const std::string& dir, const pipeline::PipelineConfig& config) {
  const auto source = pipeline::open_tum_source(dir, config.dataset);
  DatasetCheck c =
      check_frame_source(*source, config, pipeline::simulator_sign(dir, source->has_labels()), true);
  c.dir = dir;
  return c;
}

DatasetCheck check_frame_source(const pipeline::FrameSource& source, const pipeline::PipelineConfig& config,
                                const std::string& sim_sign, bool may_use_rig) {
  DatasetCheck c;
  // 1. What was opened: layout, camera, timing, ground truth, labels.
  c.dir = source.name();
  c.layout = source.layout();
  c.camera = source.camera();
  c.camera_source = source.camera_source();
  c.labels = source.has_labels();
  timing(source, c);
  ground_truth(source, config.eval.gt_max_dt_s, c);
  // 2. The checks a run makes before its first frame, on the same sample frames.
  const std::vector<RgbdFrame> sample = sample_frames(source, &c.unreadable);
  c.sampled = sample.size() + c.unreadable.size();
  pipeline::PipelineConfig resolved = config;
  c.depth_registration = pipeline::resolve_depth_registration(resolved, sample, c.camera,
                                                              source.depth_registered_by(), may_use_rig);
  c.depth_camera = source.depth_camera();
  c.depth_scale = pipeline::check_depth_scale(sample, c.camera.depth_factor);
  // 3. The segmenter a run would choose.
  const pipeline::SegmenterChoice choice =
      pipeline::choose_segmenter(pipeline::parse_segmenter_spec(""), config, sim_sign);
  c.segmenter = (choice.type == "onnx" ? choice.model : choice.type) + " (" + choice.reason + ")";
  pipeline::record_segmenter_choice(resolved, choice);
  c.settings = resolved;
  return c;
}

std::string format_dataset_check(const DatasetCheck& c, bool all_settings) {
  std::ostringstream o;
  const PinholeCamera& k = c.camera;
  o << "dataset: " << c.dir << " (" << c.layout << ")\n";
  o << fmt::format("frames: {}, t {:.3f} .. {:.3f} s ({:.1f} s)", c.frames, c.t_first_s, c.t_last_s,
                   c.t_last_s - c.t_first_s);
  if (c.median_step_s > 0)
    o << fmt::format(", median step {:.1f} ms ({:.1f} Hz), longest {:.1f} ms after frame {}",
                     1e3 * c.median_step_s, 1.0 / c.median_step_s, 1e3 * c.largest_gap_s,
                     c.largest_gap_after);
  o << "\n";
  if (c.median_step_s > 0 && c.largest_gap_s > 5 * c.median_step_s)
    o << fmt::format(
        "warning: a gap of {:.2f} s after frame {}: tracking may be lost there (dropped frames?)\n",
        c.largest_gap_s, c.largest_gap_after);
  o << fmt::format("camera: {}x{}, fx {:g} fy {:g} cx {:g} cy {:g}, {}, depth factor {:g} (from {})\n",
                   k.width, k.height, k.fx, k.fy, k.cx, k.cy,
                   k.has_distortion() ? "with distortion" : "no distortion", k.depth_factor, c.camera_source);
  if (c.gt_poses == 0)
    o << "ground truth: none (no ATE; s3m eval can score the trajectory later)\n";
  else
    o << fmt::format("ground truth: {} poses, camera path {:.2f} m; {} of {} frames have a pose\n",
                     c.gt_poses, c.gt_path_m, c.frames_with_gt, c.frames);
  o << "labels: " << (c.labels ? "ground-truth label images (segmentation and map mIoU)" : "none") << "\n";
  o << fmt::format("sample: frames 0, 20, ... ({} read)\n", c.sampled);
  for (const auto& u : c.unreadable) o << "warning: unreadable " << u << "\n";
  o << "depth: " << c.depth_registration << "\n";
  if (!c.depth_camera.empty()) o << c.depth_camera << "\n";  // "depth camera 848x480 fx ... at (...) cm ..."
  if (c.depth_scale.warning.empty())
    o << fmt::format("depth scale: median {:.2f} m over {} frame(s), plausible\n", c.depth_scale.median_m,
                     c.depth_scale.frames);
  else
    o << "warning: " << c.depth_scale.warning << "\n";
  o << "segmenter: " << c.segmenter << "\n";
  o << settings_summary(c.settings);
  if (all_settings) o << effective_config_text(c.settings);
  return o.str();
}

}  // namespace s3m::run
