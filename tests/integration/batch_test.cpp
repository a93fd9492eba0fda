// `s3m batch` end to end (s3m::batch): three short flights through one simulated office
// (fleet_fixture.hpp) and one broken recording, run by the local engine and by Slurm on a
// single-node cluster (tests/batch/slurm_cluster.sh, started by ctest around these tests; the
// Slurm test is skipped where that cluster is not running). The three runs succeed, the broken one
// is reported with its error, their merge is at least as good as each run where that run looked
// and covers what they observed; both engines merge the same map; a re-run runs only the broken
// recording.
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <map>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "fleet_fixture.hpp"
#include "pipeline_fixture.hpp"

namespace s3m::it {
namespace {

using nlohmann::json;

const char* const kRecordings[] = {"figure8", "figure8_yaw20", "handheld", "broken"};

// The manifest: runs cut to kFleetFrames frames, deterministic (identical maps on either engine).
fs::path write_manifest(const fs::path& dir) {
  fs::create_directories(dir / "broken");
  std::ofstream(dir / "broken" / "NOTE") << "the recorder crashed: no frames\n";
  const fs::path manifest = dir / "manifest.yaml";
  std::ofstream(manifest) << "defaults:\n"
                          << "  config: " << S3M_TEST_DATA_DIR << "/../../config/sim.yaml\n"
                          << "  segmenter: oracle\n  deterministic: true\n  max_frames: " << kFleetFrames
                          << "\n"
                          << "recordings:\n"
                          << "  - {name: figure8, path: " << flight_a_dir() << "}\n"
                          << "  - {name: figure8_yaw20, path: " << flight_b_dir() << "}\n"
                          << "  - {name: handheld, path: " << flight_handheld_dir() << "}\n"
                          << "  - path: broken\n";
  return manifest;
}

// The s3m binary's size and modification time: the batch runs it, so a new s3m makes the cached
// batch again even when this test binary did not change. The copies an earlier s3m of this build
// folder made are removed.
fs::path batch_cache_dir() {
  const fs::path s3m = fs::canonical(S3M_BINARY);
  const std::string prefix = "s3m_it_batch_local_s";
  const std::string base = prefix + std::to_string(fs::file_size(s3m)) + "_" +
                           std::to_string(fs::last_write_time(s3m).time_since_epoch().count());
  const fs::path dir = build_stamped(fs::temp_directory_path() / base);  // base_b<build folder>_<test binary>
  const std::string own = dir.filename().string();
  const std::string build_key = own.substr(base.size(), own.find('_', base.size() + 1) - base.size() + 1);
  std::error_code ec;
  for (const auto& e : fs::directory_iterator(fs::temp_directory_path(), ec)) {
    const std::string name = e.path().filename().string();
    if (name.rfind(prefix, 0) == 0 && name.find(build_key) != std::string::npos && name.rfind(own, 0) != 0) {
      std::error_code ignored;
      fs::remove_all(e.path(), ignored);
    }
  }
  return dir;
}

// The local engine's batch, made once (cached_folder): DIR/manifest.yaml, DIR/out (the batch),
// DIR/exit_code, DIR/log.
const fs::path& local_batch() {
  static const fs::path d = cached_folder(batch_cache_dir(), "exit_code", [](const fs::path& tmp) {
    const fs::path manifest = write_manifest(tmp);
    std::string log;
    const int rc = run_s3m(
        "batch '" + manifest.string() + "' --out '" + (tmp / "out").string() + "' --engine local --jobs 2",
        tmp / "log", &log);
    std::ofstream(tmp / "exit_code") << rc;
  });
  return d;
}

json summary_of(const fs::path& out) { return json::parse(read_bytes((out / "summary.json").string())); }

void expect_runs_and_merge(const json& s) {
  ASSERT_EQ(s["runs"].size(), 4u);
  for (int k = 0; k < 3; ++k) {
    const json& r = s["runs"][k];
    EXPECT_EQ(r["name"], kRecordings[k]);
    EXPECT_EQ(r["status"], "done") << r.dump();
    EXPECT_EQ(r["frames"], kFleetFrames);
    EXPECT_LT(r["ate_rmse_m"].get<double>(), 0.02) << r.dump();
    EXPECT_GT(r["map"]["voxels"].get<int>(), 5000);
  }
  const json& broken = s["runs"][3];
  EXPECT_EQ(broken["status"], "failed");
  EXPECT_EQ(broken["exit_code"], 1);
  EXPECT_NE(broken["error"].get<std::string>().find("broken/rgb.txt: file not found"), std::string::npos)
      << broken.dump();
  EXPECT_EQ(s["failed"], 1);
  const json& m = s["merged"];
  ASSERT_EQ(m["status"], "merged") << m.dump();
  EXPECT_EQ(m["world"], "figure8");
  ASSERT_EQ(m["runs"].size(), 3u);
  for (const json& r : m["runs"]) EXPECT_NE(r["status"], "not placed") << r.dump();
}

// Measured (100 frames each): merged 0.866/0.850/0.881 where figure8/figure8_yaw20/handheld looked,
// against their own 0.854/0.843/0.877; on all their voxels 0.872 against 0.664/0.557/0.677;
// coverage 1.000 of 20 958 voxels.
void expect_merged_map_quality(const json& s) {
  const json& map = s["merged"]["map"];
  std::printf("merged map: %s\n", map.dump().c_str());
  double best_on_union = 0, best_own = 0;
  for (int k = 0; k < 3; ++k) {
    const json& r = s["runs"][k]["map"];
    std::printf("  %s: %s\n", kRecordings[k], r.dump().c_str());
    EXPECT_GE(r["merged_miou_on_own"].get<double>(), r["miou_on_own"].get<double>())
        << kRecordings[k] << ": merging must not spoil where this run looked";
    best_on_union = std::max(best_on_union, r["miou_on_union"].get<double>());
    if (r["miou_on_own"].get<double>() > best_own) best_own = r["miou_on_own"];
  }
  EXPECT_GE(map["miou"].get<double>(), best_on_union);
  EXPECT_GE(map["coverage_of_union"].get<double>(), 0.99);
  EXPECT_GT(map["union_observed_gt_voxels"].get<int>(), 15000);
}

TEST(Batch, LocalEngineRunsTheFlightsReportsTheBrokenOneAndMerges) {
  const fs::path& d = local_batch();
  const std::string log = read_bytes((d / "log").string());
  EXPECT_EQ(read_bytes((d / "exit_code").string()), "1") << "a recording failed: " << log;
  EXPECT_NE(log.find("1 of 4 recordings did not run"), std::string::npos) << log;
  const json s = summary_of(d / "out");
  expect_runs_and_merge(s);
  expect_merged_map_quality(s);
  const std::string html = read_bytes((d / "out" / "summary.html").string());
  EXPECT_NE(html.find("broken/rgb.txt: file not found"), std::string::npos);
  // The scripts name s3m by its absolute path.
  const std::string task = read_bytes((d / "out" / "jobs" / "task_0.sh").string());
  EXPECT_NE(task.find("'" + fs::canonical(S3M_BINARY).string() + "' run '" + flight_a_dir()),
            std::string::npos)
      << task;
}

TEST(Batch, RerunRunsOnlyTheBrokenRecording) {
  const fs::path out = local_batch() / "out";
  std::map<std::string, fs::file_time_type> before;
  const std::vector<std::string> untouched = {"runs/figure8/metrics.json",  "runs/figure8_yaw20/map.ot",
                                              "runs/handheld/slam_map.bin", "logs/figure8.log",
                                              "logs/handheld.exit",         "merged/map.ot",
                                              "merged/merge.json"};
  for (const auto& f : untouched) before[f] = fs::last_write_time(out / f);
  const auto broken_log = fs::last_write_time(out / "logs/broken.log");
  std::string log;
  EXPECT_EQ(run_s3m("batch '" + (local_batch() / "manifest.yaml").string() + "' --out '" + out.string() +
                        "' --engine local",
                    local_batch() / "rerun.log", &log),
            1)
      << log;
  EXPECT_NE(log.find("1 of 4 recordings to run"), std::string::npos) << log;
  EXPECT_NE(log.find("running broken"), std::string::npos) << log;
  EXPECT_EQ(log.find("running figure8"), std::string::npos) << log;
  for (const auto& f : untouched) EXPECT_EQ(fs::last_write_time(out / f), before[f]) << f << " was touched";
  EXPECT_NE(fs::last_write_time(out / "logs/broken.log"), broken_log) << "the broken recording ran again";
  expect_runs_and_merge(summary_of(out));
}

// The cluster ctest starts (slurm_cluster_start) exports SLURM_CONF to this test.
bool slurm_running(std::string& why) {
  const char* conf = std::getenv("SLURM_CONF");
  if (!conf || !fs::exists(conf)) {
    why =
        "no Slurm test cluster (SLURM_CONF unset or missing; ctest starts one with "
        "tests/batch/slurm_cluster.sh)";
    return false;
  }
  if (std::system("sinfo -h > /dev/null 2>&1") != 0) {
    why = std::string("the Slurm test cluster of ") + conf + " does not answer sinfo";
    return false;
  }
  return true;
}

TEST(Batch, SlurmEngineMergesTheSameMapAsTheLocalOne) {
  std::string why;
  if (!slurm_running(why)) GTEST_SKIP() << why;
  const fs::path local = local_batch() / "out", out = scratch_dir() / "batch_slurm";
  fs::remove_all(out);
  std::string log;
  EXPECT_EQ(run_s3m("batch '" + (local_batch() / "manifest.yaml").string() + "' --out '" + out.string() +
                        "' --engine slurm --wait",
                    scratch_dir() / "batch_slurm.log", &log),
            1)
      << log;
  EXPECT_NE(log.find("submitted: sbatch --parsable '" + out.string() + "/jobs/runs.sbatch'"),
            std::string::npos)
      << log;
  EXPECT_NE(log.find("--dependency=afterany:"), std::string::npos) << log;
  const json s = summary_of(out);
  expect_runs_and_merge(s);
  // Each run was a task of the array (Slurm's own output file per task).
  int task_outputs = 0;
  for (const auto& e : fs::directory_iterator(out / "logs"))
    task_outputs += e.path().filename().string().rfind("slurm-runs-", 0) == 0;
  EXPECT_EQ(task_outputs, 4);
  for (const char* f : {"map.ot", "slam_map.bin", "kept_clouds.bin"})
    EXPECT_TRUE(read_bytes((out / "merged" / f).string()) == read_bytes((local / "merged" / f).string()))
        << f << " differs between the engines";
  EXPECT_EQ(s["merged"]["map"].dump(), summary_of(local)["merged"]["map"].dump());
}

TEST(Batch, DryRunWritesAndPrintsTheScriptsAndRunsNothing) {
  const fs::path dir = scratch_dir() / "batch_dry";
  fs::remove_all(dir);
  const fs::path manifest = write_manifest(dir);
  std::string log;
  ASSERT_EQ(run_s3m("batch '" + manifest.string() + "' --out '" + (dir / "out").string() +
                        "' --engine slurm --dry-run",
                    dir / "log", &log),
            0)
      << log;
  for (const char* s : {"#SBATCH --array=0,1,2,3", "#SBATCH --cpus-per-task=1", "#SBATCH --mem=",
                        "would run: sbatch --parsable '", "--dependency=afterany:ARRAY_JOB", "--merge-stage"})
    EXPECT_NE(log.find(s), std::string::npos) << s << "\n" << log;
  EXPECT_NE(log.find("'" + fs::canonical(S3M_BINARY).string() + "' run"), std::string::npos) << log;
  EXPECT_TRUE(fs::exists(dir / "out" / "jobs" / "runs.sbatch"));
  EXPECT_FALSE(fs::exists(dir / "out" / "runs"));
  EXPECT_FALSE(fs::exists(dir / "out" / "summary.json"));
}

}  // namespace
}  // namespace s3m::it
