// The batch manifest (s3m::batch::load_manifest) and the job scripts (make_plan, read_status).
#include <filesystem>
#include <fstream>

#include <gtest/gtest.h>
#include <unistd.h>

#include "s3m/batch/manifest.hpp"
#include "s3m/batch/plan.hpp"
#include "s3m/core/error.hpp"

namespace s3m::batch {
namespace {
namespace fs = std::filesystem;

fs::path scratch_root() {
  return fs::temp_directory_path() / ("s3m_batch_unit_" + std::to_string(::getpid()));
}

// This process's scratch folders go when the tests end.
struct RemoveScratch : ::testing::Environment {
  void TearDown() override { fs::remove_all(scratch_root()); }
};
const auto* const kRemoveScratch = ::testing::AddGlobalTestEnvironment(new RemoveScratch);

fs::path scratch(const std::string& name) {
  const fs::path d = scratch_root() / name;
  fs::remove_all(d);
  fs::create_directories(d);
  return d;
}

fs::path write(const fs::path& dir, const std::string& text) {
  std::ofstream(dir / "manifest.yaml") << text;
  return dir / "manifest.yaml";
}

std::string error_of(const fs::path& manifest) {
  try {
    load_manifest(manifest.string());
  } catch (const Error& e) {
    return e.what();
  }
  return "";
}

std::string read(const std::string& path) {
  std::ifstream in(path);
  return std::string(std::istreambuf_iterator<char>(in), {});
}

TEST(BatchManifest, DefaultsApplyPathsResolveAgainstTheManifestAndNamesDefaultToTheFolder) {
  const fs::path d = scratch("defaults");
  const Manifest m =
      load_manifest(write(d,
                          "defaults: {config: presets/sim.yaml, segmenter: oracle, deterministic: true}\n"
                          "recordings:\n"
                          "  - path: flights/monday\n"
                          "  - {path: /data/tuesday.bag, name: tue, max_frames: 50, config: /c.yaml}\n")
                        .string());
  ASSERT_EQ(m.recordings.size(), 2u);
  EXPECT_EQ(m.recordings[0].name, "monday");
  EXPECT_EQ(m.recordings[0].path, (d / "flights/monday").string());
  EXPECT_EQ(m.recordings[0].run.config, (d / "presets/sim.yaml").string());
  EXPECT_EQ(m.recordings[0].run.segmenter, "oracle");
  EXPECT_TRUE(m.recordings[0].run.deterministic);
  EXPECT_EQ(m.recordings[0].run.max_frames, -1);
  EXPECT_EQ(m.recordings[1].name, "tue");
  EXPECT_EQ(m.recordings[1].run.config, "/c.yaml");
  EXPECT_EQ(m.recordings[1].run.max_frames, 50);
  EXPECT_TRUE(m.recordings[1].run.deterministic) << "a default it does not set";
  EXPECT_EQ(m.merge_config, (d / "presets/sim.yaml").string()) << "the merge takes the defaults' preset";
}

TEST(BatchManifest, MistakesAreRefusedWithFileLineAndKey) {
  const fs::path d = scratch("mistakes");
  std::string e = error_of(write(d, "recordings:\n  - path: a\n    segmentor: oracle\n"));
  EXPECT_NE(e.find("manifest.yaml"), std::string::npos) << e;
  EXPECT_NE(e.find("segmentor"), std::string::npos) << e;
  EXPECT_NE(e.find(":3"), std::string::npos) << e;
  e = error_of(write(d, "recordings:\n  - path: x/a\n  - path: y/a\n"));
  EXPECT_NE(e.find("a second recording named 'a'"), std::string::npos) << e;
  e = error_of(write(d, "recordings:\n  - name: a\n"));
  EXPECT_NE(e.find("without 'path'"), std::string::npos) << e;
  e = error_of(write(d, "recordings: []\n"));
  EXPECT_NE(e.find("no recordings"), std::string::npos) << e;
  e = error_of(write(d, "recordings:\n  - {path: a, name: 'two words'}\n"));
  EXPECT_NE(e.find("cannot name a folder"), std::string::npos) << e;
  e = error_of(write(d, "defaults: {max_frames: many}\nrecordings:\n  - path: a\n"));
  EXPECT_NE(e.find("max_frames"), std::string::npos) << e;
}

TEST(BatchPlan, ScriptsNameS3mByAbsolutePathAndReRunOnlyWhatIsNotDone) {
  const fs::path d = scratch("plan");
  const fs::path manifest = write(d,
                                  "defaults: {deterministic: true, max_frames: 10}\n"
                                  "recordings:\n  - path: one\n  - path: two\n  - path: three\n");
  const std::string s3m = "/bin/true";  // any absolute file: the scripts only name it
  Plan p = make_plan(manifest.string(), (d / "out").string(), s3m);
  EXPECT_EQ(p.todo, (std::vector<std::size_t>{0, 1, 2}));
  EXPECT_EQ(p.task.cpus, 1);
  const std::string task = read(p.paths.task_script(1));
  EXPECT_NE(task.find("'/bin/true' run '" + (d / "two").string() + "' --out '" + p.paths.dir +
                      "/runs/two' --deterministic --max-frames 10 --no-report --no-session-mcap > '" +
                      p.paths.dir + "/logs/two.log' 2>&1"),
            std::string::npos)
      << task;
  EXPECT_NE(read(p.paths.array_script()).find("#SBATCH --array=0,1,2\n"), std::string::npos);
  EXPECT_NE(read(p.paths.merge_script())
                .find("exec '/bin/true' batch '" + manifest.string() + "' --out '" + p.paths.dir +
                      "' --merge-stage"),
            std::string::npos);
  // one done (exit 0 and metrics.json), two failed, three never finished (a log, no exit file).
  fs::create_directories(d / "out/runs/one");
  fs::create_directories(d / "out/logs");
  std::ofstream(d / "out/runs/one/metrics.json") << "{}";
  std::ofstream(d / "out/logs/one.exit") << "0\n";
  std::ofstream(d / "out/logs/two.log") << "[info] run: ...\ns3m: error: two/rgb.txt: file not found\n";
  std::ofstream(d / "out/logs/two.exit") << "1\n";
  std::ofstream(d / "out/logs/three.log") << "slurmstepd: error: *** JOB 7 CANCELLED ***\n";
  EXPECT_EQ(read_status(p.paths, p.manifest.recordings[0]).state, RunState::kDone);
  const RunStatus two = read_status(p.paths, p.manifest.recordings[1]);
  EXPECT_EQ(two.state, RunState::kFailed);
  EXPECT_EQ(two.exit_code, 1);
  EXPECT_EQ(two.error, "two/rgb.txt: file not found");
  const RunStatus three = read_status(p.paths, p.manifest.recordings[2]);
  EXPECT_EQ(three.state, RunState::kNotFinished);
  EXPECT_NE(three.error.find("CANCELLED"), std::string::npos) << three.error;
  p = make_plan(manifest.string(), (d / "out").string(), s3m);
  EXPECT_EQ(p.todo, (std::vector<std::size_t>{1, 2}));
  EXPECT_NE(read(p.paths.array_script()).find("#SBATCH --array=1,2\n"), std::string::npos);
  EXPECT_EQ(shell_quote("it's"), "'it'\\''s'");
}

}  // namespace
}  // namespace s3m::batch
