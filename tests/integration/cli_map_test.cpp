// `s3m query`, `s3m export` and `s3m view` (the built binary, as a user runs them) take the run
// folder that `s3m run --out` printed as well as its map.ot: same output either way, and a folder
// without a map (a --slam-only run) is named with the reason; an export never replaces the map it reads.
#include "pipeline_fixture.hpp"

namespace s3m::it {
namespace {

const auto* const kCleanup = ::testing::AddGlobalTestEnvironment(new ScratchCleanup);

int s3m(const std::string& args, const fs::path& log_path, std::string* log) {
  return run_s3m(args, log_path, log);
}

TEST(CliMap, RunFolderStandsForItsMap) {
  const fs::path dir = scratch_dir() / "cli_map";
  fs::remove_all(dir);
  fs::create_directories(dir);
  const std::string run = "run '" + sequence_dir() + "' --config '" + std::string(S3M_TEST_DATA_DIR) +
                          "/../../config/sim.yaml' --deterministic --no-report --max-frames 20 --out ";
  std::string log, by_file, by_folder;
  ASSERT_EQ(s3m(run + "'" + (dir / "out").string() + "'", dir / "run.log", &log), 0) << log;
  ASSERT_EQ(
      s3m("query '" + (dir / "out" / "map.ot").string() + "' --class wall --json", dir / "a.log", &by_file),
      0)
      << by_file;
  ASSERT_EQ(s3m("query '" + (dir / "out").string() + "' --class wall --json", dir / "b.log", &by_folder), 0)
      << by_folder;
  EXPECT_EQ(by_file, by_folder);
  EXPECT_NE(by_folder.find("wall"), std::string::npos) << by_folder;
  ASSERT_EQ(s3m("export '" + (dir / "out").string() + "' --ply '" + (dir / "map.ply").string() + "'",
                dir / "c.log", &log),
            0)
      << log;
  EXPECT_GT(fs::file_size(dir / "map.ply"), 1000u);
  // An export onto the map it reads is refused, by path and through a hard link, and the map stays.
  const std::string map_bytes = read_bytes((dir / "out" / "map.ot").string());
  fs::create_hard_link(dir / "out" / "map.ot", dir / "linked.ot");
  for (const fs::path& target : {dir / "out" / "map.ot", dir / "linked.ot"}) {
    EXPECT_NE(s3m("export '" + (dir / "out").string() + "' --color-ot '" + target.string() + "'",
                  dir / "g.log", &log),
              0);
    EXPECT_NE(log.find("is the map being exported"), std::string::npos) << log;
  }
  EXPECT_NE(s3m("export '" + (dir / "out").string() + "' --ply '" + (dir / "x.ply").string() + "' --bt '" +
                    (dir / "x.ply").string() + "'",
                dir / "h.log", &log),
            0);
  EXPECT_NE(log.find("is also the path of another export"), std::string::npos) << log;
  EXPECT_EQ(read_bytes((dir / "out" / "map.ot").string()), map_bytes);
  ASSERT_EQ(s3m("view '" + (dir / "out").string() + "'", dir / "d.log", &log), 0) << log;
  EXPECT_TRUE(fs::exists(dir / "out" / "map_viewer" / "index.html")) << log;
  // A --slam-only run writes no map: the folder is refused with the reason.
  ASSERT_EQ(s3m(run + "'" + (dir / "slam").string() + "' --slam-only", dir / "e.log", &log), 0) << log;
  EXPECT_NE(s3m("query '" + (dir / "slam").string() + "' --class wall", dir / "f.log", &log), 0);
  EXPECT_NE(log.find("is a folder without map.ot (a --slam-only run?)"), std::string::npos) << log;
}

}  // namespace
}  // namespace s3m::it
