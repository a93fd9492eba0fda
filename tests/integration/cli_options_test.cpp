// The CLI as a user meets it with bad options: each is refused before any work with a message that
// names the option and the value, never as an "unexpected error", and no recording is written over
// without --force; a run stopped with Ctrl-C says so and exits 130, so a script can tell it from a
// complete result.
#include <fstream>

#include <nlohmann/json.hpp>

#include "pipeline_fixture.hpp"

namespace s3m::it {
namespace {

const auto* const kCleanup = ::testing::AddGlobalTestEnvironment(new ScratchCleanup);

struct Refusal {
  std::string args;
  std::string message;
};

TEST(CliOptions, BadValuesAreRefusedNamingTheOptionAndValue) {
  const fs::path dir = scratch_dir() / "cli_options";
  fs::remove_all(dir);
  fs::create_directories(dir);
  std::ofstream(dir / "a_file") << "not a folder";
  fs::create_directories(dir / "recording");
  std::ofstream(dir / "recording" / "rgb.txt") << "# a real camera's list\n";
  const std::string seq = "'" + sequence_dir() + "'", file = "'" + (dir / "a_file").string() + "'";
  const std::vector<Refusal> cases = {
      {"run " + seq + " --max-frames -3 --out '" + (dir / "r").string() + "'", "'-3' is not a count"},
      {"segeval --pred-dir " + seq + " --gt-dir " + seq + " --max-images 2.5", "'2.5' is not a count"},
      {"sim --frames 5 --snapshots 1,abc --out '" + (dir / "s").string() + "'",
       "--snapshots: 'abc' is not a frame number"},
      {"sim --frames 5 --snapshots 9 --out '" + (dir / "s").string() + "'",
       "--snapshots: frame 9 is outside the sequence (5 frames)"},
      {"sim --frames 5 --out " + file, "is a file, not a folder"},
      {"demo --out " + file, "is a file, not a folder"},
      {"sim --frames 5 --out '" + (dir / "recording").string() + "'",
       "holds a recording (rgb.txt, no sim.yaml)"},
      {"vocab " + seq + "/rgb --features 1000000000 --out '" + (dir / "v.bin").string() + "'",
       "--features 1000000000 per image is over the limit of 100000"},
  };
  for (const Refusal& c : cases) {
    std::string log;
    // CLI11's own validation errors exit 105, s3m's errors 1.
    EXPECT_EQ(run_s3m(c.args, dir / "log.txt", &log),
              c.args.rfind("run", 0) == 0 || c.args.rfind("segeval", 0) == 0 ? 105 : 1)
        << c.args << "\n"
        << log;
    EXPECT_NE(log.find(c.message), std::string::npos) << c.args << "\n" << log;
    EXPECT_EQ(log.find("unexpected error"), std::string::npos) << log;
  }
  EXPECT_FALSE(fs::exists(dir / "s")) << "a refused sim wrote nothing";
  EXPECT_FALSE(fs::exists(dir / "v.bin"));
  EXPECT_EQ(read_bytes((dir / "a_file").string()), "not a folder");
  EXPECT_EQ(read_bytes((dir / "recording" / "rgb.txt").string()), "# a real camera's list\n");
  // With --force it is written over, and a folder s3m sim made (sim.yaml) may be rendered again.
  std::string log;
  ASSERT_EQ(
      run_s3m("sim --frames 5 --force --out '" + (dir / "recording").string() + "'", dir / "log.txt", &log),
      0)
      << log;
  EXPECT_TRUE(fs::exists(dir / "recording" / "sim.yaml"));
  EXPECT_EQ(run_s3m("sim --frames 5 --out '" + (dir / "recording").string() + "'", dir / "log.txt", &log), 0)
      << log;
}

TEST(CliOptions, InterruptedRunExits130AndSaysSo) {
  const fs::path dir = scratch_dir() / "cli_interrupt";
  fs::remove_all(dir);
  fs::create_directories(dir);
  const fs::path out = dir / "out", log_path = dir / "run.log";
  // SIGINT once the run has started (its first log line is written after the handler is installed).
  const std::string script = std::string(S3M_BINARY) + " run '" + sequence_dir() +
                             "' --deterministic --no-report --out '" + out.string() + "' > '" +
                             log_path.string() + "' 2>&1 & p=$!; for i in $(seq 600); do grep -q 'run: ' '" +
                             log_path.string() + "' && break; sleep 0.05; done; kill -INT $p; wait $p";
  const int status = std::system(script.c_str());  // POSIX sh
  const std::string log = read_bytes(log_path.string());
  ASSERT_TRUE(WIFEXITED(status)) << log;
  EXPECT_EQ(WEXITSTATUS(status), 130) << log;
  EXPECT_NE(log.find("s3m: interrupted: run: stopped after"), std::string::npos) << log;
  // The signal may land before the first frame (then nothing is written, and the message says so)
  // or after it (then the frames so far are written, marked interrupted).
  if (log.find("is left as it was") != std::string::npos) {
    EXPECT_FALSE(fs::exists(out / "metrics.json")) << log;
    return;
  }
  const auto metrics = nlohmann::json::parse(read_bytes((out / "metrics.json").string()));
  EXPECT_TRUE(metrics["interrupted"].get<bool>());
}

}  // namespace
}  // namespace s3m::it
