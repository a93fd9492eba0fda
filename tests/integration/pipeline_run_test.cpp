// End-to-end: `s3m run` (as a library call) on a short simulated UAV flight with the noisy oracle
// segmenter, checked against the simulator's ground truth.
#include <nlohmann/json.hpp>

#include "pipeline_fixture.hpp"
#include "s3m/core/error.hpp"
#include "s3m/io/ply.hpp"
#include "s3m/io/trajectory.hpp"
#include "s3m/mapping/map_io.hpp"

namespace s3m::it {
namespace {

const auto* const kCleanup = ::testing::AddGlobalTestEnvironment(new ScratchCleanup);

// Everything `s3m run` promises to write exists and loads with the project's own readers.
void expect_loadable_outputs(const std::string& out, std::size_t frames) {
  const auto cam = io::read_tum_trajectory(out + "/trajectory_camera.txt");
  const auto robot = io::read_tum_trajectory(out + "/trajectory_robot.txt");
  const auto kfs = io::read_tum_trajectory(out + "/keyframes.txt");
  EXPECT_GT(cam.size(), frames / 2);
  EXPECT_LE(cam.size(), frames);
  ASSERT_EQ(robot.size(), cam.size());
  EXPECT_GE(kfs.size(), 2u);
  const auto map = mapping::load_semantic_map(out + "/map.ot");
  ASSERT_NE(map, nullptr);
  EXPECT_GT(map->getNumLeafNodes(), 1000u);
  const auto ply = io::read_ply(out + "/map.ply");
  EXPECT_GT(ply.size(), 1000u);
  const auto metrics = nlohmann::json::parse(read_bytes(out + "/metrics.json"));
  EXPECT_EQ(metrics["frames"].get<std::size_t>(), frames);
  EXPECT_GE(metrics["map"]["voxels"].get<std::size_t>(), ply.size());  // pruned leaves hold several voxels
}

TEST(PipelineRun, ThreadedRunWritesEveryOutputAndTracksWell) {
  pipeline::RunOptions o = options("threaded", /*deterministic=*/false);
  const pipeline::RunResult r = pipeline::run_dataset(o);
  EXPECT_FALSE(r.interrupted);
  EXPECT_EQ(r.frames_done, static_cast<std::size_t>(kFrames));
  expect_loadable_outputs(o.out_dir, kFrames);

  const auto& m = r.metrics;
  // Trajectory against ground truth: the simulator's flight is easy for ORB tracking.
  ASSERT_TRUE(m["trajectory"].contains("ate_rmse_m")) << m["trajectory"].dump();
  EXPECT_LT(m["trajectory"]["ate_rmse_m"].get<double>(), 0.05);
  EXPECT_EQ(m["trajectory"]["matched"].get<std::size_t>(), m["tracked"].get<std::size_t>());
  // The robot trajectory (T_w_c * T_c_r with the preset's calibration) against the robot ground
  // truth is as accurate as the camera's: a wrong T_c_r would add its lever arm to every pose.
  ASSERT_TRUE(m["trajectory"]["robot"].contains("ate_rmse_m")) << m["trajectory"]["robot"].dump();
  EXPECT_LT(m["trajectory"]["robot"]["ate_rmse_m"].get<double>(), 0.05);
  // Every stage was timed on every frame it ran on.
  EXPECT_EQ(m["timings_ms"]["track"]["count"].get<int>(), kFrames);
  EXPECT_EQ(m["timings_ms"]["map"]["count"].get<int>(), m["integrated"].get<int>());
  EXPECT_GT(m["map"]["raw_over_file_ratio"].get<double>(), 20.0);  // map file >= 20x smaller than raw cloud
}

TEST(PipelineRun, FusedMapBeatsSingleFrameSegmentationForEveryFusionPolicy) {
  for (const std::string policy : {"paper", "max_confidence", "bayesian"}) {
    pipeline::RunOptions o = options("fusion_" + policy, /*deterministic=*/true);
    o.config.map.fusion.policy = mapping::parse_fusion_policy(policy);
    const auto m = pipeline::run_dataset(o).metrics;
    ASSERT_TRUE(m["segmentation"].contains("miou")) << policy;
    ASSERT_TRUE(m["map"].contains("miou")) << policy << ": " << m["map"].dump();
    const double frame_miou = m["segmentation"]["miou"], map_miou = m["map"]["miou"];
    RecordProperty("miou_" + policy, std::to_string(frame_miou) + " -> " + std::to_string(map_miou));
    EXPECT_GT(map_miou, frame_miou) << policy;
    EXPECT_GT(m["map"]["gt_voxels_observed"].get<std::size_t>(), 1000u) << policy;
    // The same question in the images: the map's labels projected back vs the frames, same pixels.
    ASSERT_TRUE(m["map"].contains("reprojected")) << policy;
    const auto& r = m["map"]["reprojected"];
    EXPECT_GT(r["miou"].get<double>(), r["frame_miou"].get<double>()) << policy;
    EXPECT_GT(r["coverage"].get<double>(), 0.9) << policy;
    EXPECT_GE(r["frames"].get<int>(), 5) << policy;
  }
}

// With the shipped network the errors are systematic (the same object mislabelled from similar
// views), which fusion cannot out-vote in 3-D; reprojected into the frames the map must still beat them.
TEST(PipelineRun, FusedMapBeatsTheShippedNetworkInTheImagesForEveryFusionPolicy) {
  for (const std::string policy : {"paper", "max_confidence", "bayesian"}) {
    pipeline::RunOptions o = options("net_" + policy, /*deterministic=*/true);
    o.segmenter = "onnx:" + std::string(S3M_TEST_DATA_DIR) + "/../../models/s3m_pspnet_small.yaml";
    o.config.map.fusion.policy = mapping::parse_fusion_policy(policy);
    const auto m = pipeline::run_dataset(o).metrics;
    ASSERT_TRUE(m["map"].contains("reprojected")) << policy << ": " << m["map"].dump();
    const auto& r = m["map"]["reprojected"];
    RecordProperty("reprojected_miou_" + policy,
                   std::to_string(r["frame_miou"].get<double>()) + " -> " + std::to_string(r["miou"].get<double>()));
    EXPECT_GT(r["miou"].get<double>(), r["frame_miou"].get<double>()) << policy;
    EXPECT_GT(r["coverage"].get<double>(), 0.9) << policy;
  }
}

TEST(PipelineRun, DeterministicModeReproducesByteIdenticalOutputs) {
  pipeline::RunOptions a = options("det_a", true), b = options("det_b", true);
  pipeline::run_dataset(a);
  pipeline::run_dataset(b);
  for (const char* f : {"trajectory_camera.txt", "trajectory_robot.txt", "keyframes.txt", "map.ot", "map.ply"}) {
    const std::string x = read_bytes(a.out_dir + "/" + f), y = read_bytes(b.out_dir + "/" + f);
    EXPECT_FALSE(x.empty()) << f;
    EXPECT_TRUE(x == y) << f << " differs between two deterministic runs";
  }
}

TEST(PipelineRun, InterruptedRunLeavesLoadableOutputs) {
  pipeline::RunOptions o = options("interrupted", /*deterministic=*/false);
  o.stop_after_frames = 30;  // what the SIGINT flag does, at a reproducible point
  const pipeline::RunResult r = pipeline::run_dataset(o);
  EXPECT_TRUE(r.interrupted);
  EXPECT_EQ(r.frames_done, 30u);
  expect_loadable_outputs(o.out_dir, 30);
  EXPECT_TRUE(r.metrics["interrupted"].get<bool>());
}

TEST(PipelineRun, SlamOnlyWritesTrajectoriesAndNoMap) {
  pipeline::RunOptions o = options("slam_only", true);
  o.slam_only = true;
  o.max_frames = 40;
  o.config.dataset.depth_registration = "auto";  // sim.yaml states it; checked here from the images
  const pipeline::RunResult r = pipeline::run_dataset(o);
  EXPECT_EQ(io::read_tum_trajectory(o.out_dir + "/trajectory_camera.txt").size(),
            r.metrics["tracked"].get<std::size_t>());
  EXPECT_FALSE(fs::exists(o.out_dir + "/map.ot"));
  EXPECT_TRUE(r.metrics["map"].empty());
  EXPECT_TRUE(r.metrics["segmentation"].empty());
  // The simulator's depth is registered; the run finds so from its images and says why.
  const std::string reg = r.metrics["inputs"]["depth_registration"].get<std::string>();
  EXPECT_EQ(reg.rfind("registered (depth edges", 0), 0u) << reg;
}

TEST(PipelineRun, BadInputsAreClearErrors) {
  pipeline::RunOptions o = options("bad", true);
  o.dataset_dir = (scratch_dir() / "no_such_dataset").string();
  try {
    pipeline::run_dataset(o);
    FAIL() << "expected an error";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("no_such_dataset"), std::string::npos) << e.what();
  }
  o = options("bad", true);
  o.segmenter = "onnx:" + (scratch_dir() / "missing_model").string();
  try {
    pipeline::run_dataset(o);
    FAIL() << "expected an error";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("missing_model"), std::string::npos) << e.what();
  }
  o = options("bad", true);
  o.segmenter = "magic";
  EXPECT_THROW(pipeline::run_dataset(o), Error);
}

}  // namespace
}  // namespace s3m::it
