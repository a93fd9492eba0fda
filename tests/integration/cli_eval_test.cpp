// The `s3m eval` command itself (the built binary, as a user runs it) on a trajectory pair whose
// errors are known by construction: the estimate is the ground truth shifted by a constant
// (0.03, -0.04, 0) m, so without alignment every ATE error is exactly 0.05 m and every relative
// motion (RPE) is exact; with SE(3) alignment the shift is removed and ATE is ~0.
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <iomanip>

#include <nlohmann/json.hpp>

#include "pipeline_fixture.hpp"

namespace s3m::it {
namespace {

const auto* const kCleanup = ::testing::AddGlobalTestEnvironment(new ScratchCleanup);

// A helix with a yawing camera, 50 poses at 10 Hz; `shift` is added to every position.
void write_helix(const fs::path& path, double sx, double sy) {
  std::FILE* f = std::fopen(path.c_str(), "w");
  ASSERT_NE(f, nullptr);
  std::fprintf(f, "# timestamp tx ty tz qx qy qz qw\n");
  for (int i = 0; i < 50; ++i) {
    const double a = 0.1 * i;
    std::fprintf(f, "%.6f %.9f %.9f %.9f 0 0 %.9f %.9f\n", 10.0 + 0.1 * i, std::cos(a) + sx, std::sin(a) + sy,
                 0.01 * i, std::sin(a / 2), std::cos(a / 2));
  }
  std::fclose(f);
}

int s3m_eval(const std::string& args, const fs::path& log_path, std::string* log) {
  return run_s3m("eval " + args, log_path, log);
}

TEST(CliEval, MetricsJsonHoldsTheKnownErrors) {
  const fs::path dir = scratch_dir() / "cli_eval";
  fs::remove_all(dir);
  fs::create_directories(dir);
  write_helix(dir / "gt.txt", 0, 0);
  write_helix(dir / "est.txt", 0.03, -0.04);
  std::string log;
  for (const std::string align : {"none", "se3"}) {
    const fs::path out = dir / ("out_" + align);
    const std::string args = "--gt '" + (dir / "gt.txt").string() + "' --est '" + (dir / "est.txt").string() +
                             "' --align " + align + " --out '" + out.string() + "' --no-plots";
    ASSERT_EQ(s3m_eval(args, dir / "log.txt", &log), 0) << log;
    EXPECT_NE(log.find("metrics.json"), std::string::npos) << log;
    const auto m = nlohmann::json::parse(read_bytes((out / "metrics.json").string()));
    EXPECT_EQ(m["matched"].get<int>(), 50) << m.dump(1);
    const auto& ate = m["ate"];
    if (align == "none") {
      EXPECT_NEAR(ate["rmse_m"].get<double>(), 0.05, 1e-6);
      EXPECT_NEAR(ate["min_m"].get<double>(), 0.05, 1e-6);
      EXPECT_NEAR(ate["max_m"].get<double>(), 0.05, 1e-6);
    } else {
      EXPECT_LT(ate["rmse_m"].get<double>(), 1e-6);
    }
    // Relative motion is untouched by a constant shift.
    EXPECT_LT(m["rpe"]["trans_rmse_m"].get<double>(), 1e-6);
    EXPECT_LT(m["rpe"]["rot_rmse_deg"].get<double>(), 1e-4);
    EXPECT_GT(m["rpe"]["pairs"].get<int>(), 30);
  }
}

TEST(CliEval, FoldersStandForTheirGroundTruthAndTrajectory) {
  // --gt DATASET (its groundtruth.txt), --est RUN_A --est2 RUN_B (their trajectory_camera.txt),
  // each estimate named by its run folder rather than twice "trajectory_camera".
  const fs::path dir = scratch_dir() / "cli_eval_folders";
  fs::remove_all(dir);
  for (const char* sub : {"dataset", "run_a", "run_b", "not_a_run"}) fs::create_directories(dir / sub);
  write_helix(dir / "dataset" / "groundtruth.txt", 0, 0);
  write_helix(dir / "run_a" / "trajectory_camera.txt", 0.03, -0.04);
  write_helix(dir / "run_b" / "trajectory_camera.txt", 0, 0);
  std::string log;
  const std::string out = (dir / "out").string();
  ASSERT_EQ(s3m_eval("--gt '" + (dir / "dataset").string() + "' --est '" + (dir / "run_a").string() + "' --est2 '" +
                         (dir / "run_b").string() + "/' --align none --no-plots --out '" + out + "'",
                     dir / "log.txt", &log),
            0)
      << log;
  const auto m = nlohmann::json::parse(read_bytes(out + "/metrics.json"));
  ASSERT_EQ(m["estimates"].size(), 2u) << m.dump(1);
  EXPECT_EQ(m["estimates"][0]["name"], "run_a");
  EXPECT_EQ(m["estimates"][1]["name"], "run_b");
  EXPECT_NEAR(m["estimates"][0]["ate"]["rmse_m"].get<double>(), 0.05, 1e-6);
  EXPECT_LT(m["estimates"][1]["ate"]["rmse_m"].get<double>(), 1e-9);
  EXPECT_TRUE(fs::exists(dir / "out" / "run_a_aligned.txt"));
  // A folder without the file is named with what it probably is.
  EXPECT_NE(s3m_eval("--gt '" + (dir / "not_a_run").string() + "' --est '" + (dir / "run_a").string() + "' --no-plots",
                     dir / "log.txt", &log),
            0);
  EXPECT_NE(log.find("not_a_run is a folder without groundtruth.txt (a dataset without ground truth?)"),
            std::string::npos)
      << log;
  EXPECT_NE(s3m_eval("--gt '" + (dir / "dataset").string() + "' --est '" + (dir / "not_a_run").string() + "' --no-plots",
                     dir / "log.txt", &log),
            0);
  EXPECT_NE(log.find("not_a_run is a folder without trajectory_camera.txt"), std::string::npos) << log;
}

TEST(CliEval, SevenScenesFolderIsGroundTruth) {
  // A 7-Scenes folder as downloaded: its frame-NNNNNN.pose.txt (4x4 camera-to-world) at t = N / 30 s
  // are the ground truth; the estimate is the same helix shifted by (0.03, -0.04, 0): ATE 0.05 m.
  const fs::path dir = scratch_dir() / "cli_eval_7scenes";
  fs::remove_all(dir);
  fs::create_directories(dir / "seq-01");
  std::FILE* est = std::fopen((dir / "est.txt").c_str(), "w");
  ASSERT_NE(est, nullptr);
  for (int n = 0; n < 40; ++n) {
    const double a = 0.1 * n, c = std::cos(a), s = std::sin(a);
    char stem[64];
    std::snprintf(stem, sizeof stem, "frame-%06d", n);
    const fs::path base = dir / "seq-01" / stem;
    std::ofstream(base.string() + ".color.png");  // only their names matter to eval
    std::ofstream(base.string() + ".depth.png");
    std::ofstream(base.string() + ".pose.txt") << std::setprecision(12) << c << "\t" << -s << "\t0\t" << c << "\t\n"
                                               << s << "\t" << c << "\t0\t" << s << "\t\n"
                                               << "0\t0\t1\t" << 0.01 * n << "\t\n0\t0\t0\t1\t\n";
    std::fprintf(est, "%.6f %.9f %.9f %.9f 0 0 %.9f %.9f\n", n / 30.0, c + 0.03, s - 0.04, 0.01 * n, std::sin(a / 2),
                 std::cos(a / 2));
  }
  std::fclose(est);
  std::string log;
  const std::string out = (dir / "out").string();
  ASSERT_EQ(s3m_eval("--gt '" + (dir / "seq-01").string() + "/' --est '" + (dir / "est.txt").string() +
                         "' --align none --no-plots --out '" + out + "'",
                     dir / "log.txt", &log),
            0)
      << log;
  const auto m = nlohmann::json::parse(read_bytes(out + "/metrics.json"));
  EXPECT_EQ(m["matched"].get<int>(), 40) << m.dump(1);
  EXPECT_NEAR(m["ate"]["rmse_m"].get<double>(), 0.05, 1e-6);
  EXPECT_NEAR(m["ate"]["max_m"].get<double>(), 0.05, 1e-6);
  EXPECT_LT(m["rpe"]["trans_rmse_m"].get<double>(), 1e-6);
}

TEST(CliEval, BadInputExitsOneWithTheFileAndLine) {
  const fs::path dir = scratch_dir() / "cli_eval_bad";
  fs::remove_all(dir);
  fs::create_directories(dir);
  write_helix(dir / "gt.txt", 0, 0);
  std::ofstream(dir / "est.txt") << "# t tx ty tz qx qy qz qw\n1.0 0 0 0 0 0 0 1\n2.0 0 0 nan 0 0 0 1\n";
  std::string log;
  const int code = s3m_eval("--gt '" + (dir / "gt.txt").string() + "' --est '" + (dir / "est.txt").string() +
                                "' --no-plots",
                            dir / "log.txt", &log);
  EXPECT_EQ(code, 1) << log;
  EXPECT_NE(log.find("s3m: error: "), std::string::npos) << log;
  EXPECT_NE(log.find("est.txt:3: non-finite value 'nan' as tz"), std::string::npos) << log;
}

}  // namespace
}  // namespace s3m::it
