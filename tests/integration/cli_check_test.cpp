// `s3m check` (the built binary, as a user runs it) on the fixture's simulated sequence: every line
// says what the folder holds, and a camera file with the wrong depth factor is warned about, by
// `s3m check` and in `s3m run`'s closing summary; `s3m run` writes the settings it used.
#include <sstream>

#include "pipeline_fixture.hpp"

namespace s3m::it {
namespace {

const auto* const kCleanup = ::testing::AddGlobalTestEnvironment(new ScratchCleanup);

bool has(const std::string& log, const std::string& fragment) {
  return log.find(fragment) != std::string::npos;
}

TEST(CliCheck, SaysWhatTheFolderHolds) {
  const fs::path dir = scratch_dir() / "cli_check";
  fs::create_directories(dir);
  std::string log;
  ASSERT_EQ(run_s3m("check '" + sequence_dir() + "'", dir / "log.txt", &log), 0) << log;
  EXPECT_TRUE(has(log, "(TUM layout)")) << log;
  EXPECT_TRUE(has(log, "frames: 60, t ")) << log;
  EXPECT_TRUE(has(log, "median step 33.3 ms (30.0 Hz)")) << log;
  EXPECT_TRUE(
      has(log, "camera: 640x480, fx 525 fy 525 cx 319.5 cy 239.5, no distortion, depth factor 5000 (from "))
      << log;
  EXPECT_TRUE(has(log, "ground truth: 60 poses, camera path ")) << log;
  EXPECT_TRUE(has(log, "60 of 60 frames have a pose")) << log;
  EXPECT_TRUE(has(log, "labels: ground-truth label images")) << log;
  EXPECT_TRUE(has(log, "sample: frames 0, 20, ... (3 read)")) << log;
  EXPECT_TRUE(has(log, "depth: registered (depth edges")) << log;
  EXPECT_TRUE(has(log, "plausible")) << log;
  EXPECT_TRUE(has(log, "segmenter: oracle (simulator sequence (sim.yaml)")) << log;
  EXPECT_FALSE(has(log, "warning")) << log;

  // The same camera said to be in millimetres: the depth reads 5x too far, and the check says so.
  std::string yaml = read_bytes(sequence_dir() + "/camera.yaml");
  yaml.replace(yaml.find("depth_factor: 5000"), 18, "depth_factor: 1000");
  std::ofstream(dir / "camera_mm.yaml") << yaml;
  ASSERT_EQ(run_s3m("check '" + sequence_dir() + "' --camera '" + (dir / "camera_mm.yaml").string() + "'",
                    dir / "log.txt", &log),
            0)
      << log;
  EXPECT_TRUE(has(log, "warning: depth scale check: median depth")) << log;
  EXPECT_TRUE(has(log, "with depth factor 5000 it would be")) << log;
  EXPECT_TRUE(has(log, "depth factor 1000 (from " + (dir / "camera_mm.yaml").string() + " (dataset.camera))"))
      << log;

  // A folder s3m cannot read: exit 1 and the reason, as s3m run would say it.
  EXPECT_EQ(run_s3m("check '" + dir.string() + "'", dir / "log.txt", &log), 1) << log;
  EXPECT_TRUE(has(log, "rgb.txt: file not found")) << log;
}

TEST(CliRun, SummaryRepeatsTheDepthScaleWarning) {
  // A preset whose camera says millimetres for the sequence's 5000-per-metre depth: the run goes
  // on, and its closing summary (what a user reads after a long run) repeats the warning.
  const fs::path dir = scratch_dir() / "cli_run_depth_scale";
  fs::remove_all(dir);
  fs::create_directories(dir);
  std::string yaml = read_bytes(sequence_dir() + "/camera.yaml");
  yaml.replace(yaml.find("depth_factor: 5000"), 18, "depth_factor: 1000");
  std::ofstream(dir / "camera_mm.yaml") << yaml;
  std::ofstream(dir / "preset.yaml") << "dataset: {camera: " << (dir / "camera_mm.yaml").string() << "}\n";
  std::string log;
  ASSERT_EQ(run_s3m("run '" + sequence_dir() + "' --config '" + (dir / "preset.yaml").string() +
                        "' --slam-only --deterministic --no-report --max-frames 3 --out '" +
                        (dir / "out").string() + "'",
                    dir / "log.txt", &log),
            0)
      << log;
  const auto summary = log.find("frames: 3/");
  ASSERT_NE(summary, std::string::npos) << log;
  EXPECT_NE(log.find("warning: depth scale check: median depth", summary), std::string::npos) << log;
  EXPECT_NE(log.find("with depth factor 5000 it would be", summary), std::string::npos) << log;
}

TEST(CliRun, SummarySaysWhyThereIsNoAte) {
  // Ground truth whose clock is 1000 s off the frames': no ATE, and the summary says why.
  const fs::path seq =
      linked_copy("cli_run_gt_offset", [](const fs::path& rel) { return rel == "groundtruth.txt"; });
  std::ifstream in(sequence_dir() + "/groundtruth.txt");
  std::ofstream gt(seq / "groundtruth.txt");
  for (std::string line; std::getline(in, line);) {
    if (line.empty() || line[0] == '#') continue;
    std::istringstream fields(line);
    double t = 0;
    std::string rest;
    fields >> t;
    std::getline(fields, rest);
    gt << std::fixed << t + 1000 << rest << "\n";
  }
  gt.close();
  std::string log;
  const fs::path out = scratch_dir() / "cli_run_gt_offset_out";
  fs::remove_all(out);
  ASSERT_EQ(
      run_s3m("run '" + seq.string() + "' --slam-only --deterministic --no-report --max-frames 5 --out '" +
                  out.string() + "'",
              scratch_dir() / "cli_run_gt_offset.log", &log),
      0)
      << log;
  EXPECT_EQ(log.find("ATE RMSE"), std::string::npos) << log;
  EXPECT_NE(log.find("ATE: not computed: eval 's3m camera': only 0 of 5 estimated poses"), std::string::npos)
      << log;
  EXPECT_NE(log.find("ground truth 1001.000000.."), std::string::npos) << log;
}

TEST(CliRun, WritesTheEffectiveConfigWhichRerunsTheSame) {
  // config_effective.yaml holds every setting the run used; run again with it as the preset, the
  // trajectory is the same and so is the file (but for the comment naming the preset read).
  const fs::path dir = scratch_dir() / "cli_run_effective_config";
  fs::remove_all(dir);
  fs::create_directories(dir);
  std::ofstream(dir / "preset.yaml")
      << "slam: {features: {depth_discontinuity_ratio: 0.05}}\ncloud: {max_depth_m: 3.5}\n";
  const auto run = [&](const fs::path& preset, const std::string& out) {
    std::string log;
    EXPECT_EQ(run_s3m("run '" + sequence_dir() + "' --config '" + preset.string() +
                          "' --slam-only --deterministic --no-report --max-frames 20 --out '" +
                          (dir / out).string() + "'",
                      dir / "log.txt", &log),
              0)
        << log;
    return read_bytes((dir / out / "config_effective.yaml").string());
  };
  const std::string first = run(dir / "preset.yaml", "first");
  EXPECT_NE(first.find("depth_discontinuity_ratio: 0.05"), std::string::npos) << first;
  EXPECT_NE(first.find("max_depth_m: 3.5"), std::string::npos) << first;
  EXPECT_NE(first.find("deterministic: true"), std::string::npos) << first;  // --deterministic
  EXPECT_NE(first.find("# depth: registered"), std::string::npos) << first;
  const std::string second = run(dir / "first" / "config_effective.yaml", "second");
  const auto body = [](const std::string& text) { return text.substr(text.find("\ndataset:")); };
  EXPECT_EQ(body(second), body(first));
  EXPECT_EQ(read_bytes((dir / "second" / "trajectory_camera.txt").string()),
            read_bytes((dir / "first" / "trajectory_camera.txt").string()));

  // `s3m check` says which settings a run would use.
  std::string log;
  ASSERT_EQ(run_s3m("check '" + sequence_dir() + "' --config '" + (dir / "preset.yaml").string() + "'",
                    dir / "log.txt", &log),
            0)
      << log;
  EXPECT_TRUE(has(log, "settings: " + (dir / "preset.yaml").string() + "; differing from the defaults:"))
      << log;
  EXPECT_TRUE(has(log, "\n  cloud.max_depth_m: 3.5 (written)")) << log;
  EXPECT_TRUE(has(log, "\n  segmenter.type: oracle (automatic)")) << log;
  EXPECT_FALSE(has(log, "depth_discontinuity_ratio")) << log;  // written, but the default
  ASSERT_EQ(run_s3m("check '" + sequence_dir() + "' --all-settings", dir / "log.txt", &log), 0) << log;
  EXPECT_TRUE(has(log, "\n    depth_discontinuity_ratio: 0.05\n")) << log;
}

}  // namespace
}  // namespace s3m::it
