// `s3m run` without --segmenter or preset (segmenter type auto): a recording that is not a simulator
// sequence is labelled by the shipped real-image model, a simulator sequence by the oracle, and
// metrics.json says which and why, with the map's classes.
#include "pipeline_fixture.hpp"

namespace s3m::it {
namespace {

const auto* const kCleanup = ::testing::AddGlobalTestEnvironment(new ScratchCleanup);

run::RunOptions default_options(const std::string& dataset, const std::string& out_name) {
  run::RunOptions o;
  o.dataset_dir = dataset;
  o.out_dir = (scratch_dir() / out_name).string();
  fs::remove_all(o.out_dir);
  o.config.threads.deterministic = true;  // built-in defaults otherwise: segmenter.type auto
  o.max_frames = 12;  // more than the keyframes SLAM makes of it, so segmenting fewer shows
  o.report = false;
  return o;
}

TEST(RunDefaultSegmenter, RecordingWithoutSimulatorFilesGetsTheRealImageModel) {
  // The simulated sequence stripped of what marks it as one: like a real camera's TUM folder.
  const fs::path real = scratch_dir() / "real_camera";
  fs::remove_all(real);
  fs::copy(sequence_dir(), real, fs::copy_options::recursive);
  for (const char* f : {"sim.yaml", "labels.txt", "labels", "gt_voxels.txt", "groundtruth_robot.txt"})
    fs::remove_all(real / f);
  const run::RunResult r = run::run_dataset(default_options(real.string(), "out_real"));
  EXPECT_EQ(r.metrics["inputs"]["segmenter"], "deeplabv3plus_mnv2_ade20k_fast");
  EXPECT_EQ(r.metrics["inputs"]["segmenter_reason"],
            "dataset has no sim.yaml or label images: real-camera default");
  // No label images to score the others: only the frames that go into the map are segmented.
  EXPECT_EQ(r.metrics["segmented"], r.metrics["integrated"]);
  EXPECT_LT(r.metrics["segmented"].get<int>(), r.metrics["frames"].get<int>()) << r.metrics;
  EXPECT_NE(read_bytes(r.metrics["outputs"]["config_effective"]).find("segment: integrated"),
            std::string::npos);
  const auto& classes = r.metrics["map"]["class_voxels"];
  ASSERT_TRUE(classes.is_array());
  ASSERT_GT(r.metrics["map"]["voxels"].get<std::size_t>(), 0u);
  ASSERT_FALSE(classes.empty());
  double share = 0;
  std::size_t previous = SIZE_MAX;
  for (const auto& c : classes) {
    EXPECT_LE(c["voxels"].get<std::size_t>(), previous);  // most frequent first
    previous = c["voxels"].get<std::size_t>();
    share += c["share"].get<double>();
  }
  EXPECT_NEAR(share, 1.0, 1e-9);
}

TEST(RunDefaultSegmenter, SimulatorSequenceKeepsTheOracle) {
  const run::RunResult r = run::run_dataset(default_options(sequence_dir(), "out_sim"));
  EXPECT_EQ(r.metrics["inputs"]["segmenter"].get<std::string>().rfind("oracle", 0), 0u)
      << r.metrics["inputs"];
  EXPECT_EQ(r.metrics["inputs"]["segmenter_reason"],
            "simulator sequence (sim.yaml): its ground-truth labels through the noisy oracle");
  // Label images score every frame: every frame is segmented.
  EXPECT_EQ(r.metrics["segmented"], r.metrics["frames"]);
  EXPECT_NE(read_bytes(r.metrics["outputs"]["config_effective"]).find("segment: all_frames"),
            std::string::npos);
}

}  // namespace
}  // namespace s3m::it
