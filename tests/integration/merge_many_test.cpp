// N-way merges (run::merge_many, `s3m merge A B C ...`) on flights through one simulated office
// and one through another (fleet_fixture.hpp): the order follows the overlap, the runs of
// the office become one map, the other building's run is reported as not placed and kept apart.
#include <filesystem>
#include <map>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "fleet_fixture.hpp"
#include "pipeline_fixture.hpp"
#include "s3m/core/error.hpp"
#include "s3m/features/bow_vocabulary.hpp"
#include "s3m/run/merge_many.hpp"
#include "s3m/slam/io/map_io.hpp"

namespace s3m::it {
namespace {

using nlohmann::json;

int keyframes_of(const std::string& run) {
  static const auto vocab = std::make_shared<const features::Vocabulary>(
      features::Vocabulary::load(features::default_vocabulary_path()));
  return slam::load_slam_map(run + "/slam_map.bin", vocab).map.n_keyframes();
}

TEST(MergeMany, FiveRunsOneFromAnotherBuildingIsNotPlacedTheOthersMerge) {
  run::MergeManyOptions o;
  // The other building's run second: where it is listed must not matter.
  o.runs = {fleet_run("a"), fleet_run("other"), fleet_run("b"), fleet_run("handheld"), fleet_run("c")};
  o.out_dir = (scratch_dir() / "merge_five").string();
  o.config = sim_preset();
  const json j = run::merge_many(o);
  std::printf("s3m merge of five: order %s\n  overlaps %s\n", j["order"].dump().c_str(),
              j["overlaps"].dump().c_str());
  ASSERT_EQ(j["runs"].size(), 5u);
  const json& other = j["runs"][1];
  EXPECT_EQ(other["status"], "not placed");
  EXPECT_FALSE(other.contains("order"));
  const fs::path kept = other["kept_as"].get<std::string>();
  EXPECT_EQ(read_bytes((kept / "map.ot").string()), read_bytes(fleet_run("other") + "/map.ot"))
      << "kept as it was";
  EXPECT_TRUE(fs::exists(kept / "slam_map.bin"));
  // The four office runs: one world, three joined, each through a run merged before it by an
  // alignment at least min_agreeing verified pairs agree on.
  std::map<int, int> position;  // run (1-based) -> merge order
  int n_keyframes = 0;
  for (const int k : {0, 2, 3, 4}) {
    const json& r = j["runs"][k];
    EXPECT_NE(r["status"], "not placed") << r.dump();
    position[k + 1] = r["order"];
    n_keyframes += keyframes_of(o.runs[k]);
    EXPECT_TRUE(fs::exists(fs::path(o.out_dir) / ("trajectory_camera_" + std::to_string(k + 1) + ".txt")));
    if (r["status"] == "world") continue;
    EXPECT_EQ(r["status"], "joined");
    EXPECT_GE(r["agreeing_pairs"].get<int>(), o.search.min_agreeing) << r.dump();
    EXPECT_LT(position.count(r["joined_to"]) ? position[r["joined_to"]] : 0, position[k + 1]) << r.dump();
  }
  EXPECT_FALSE(fs::exists(fs::path(o.out_dir) / "trajectory_camera_2.txt"));
  EXPECT_EQ(j["order"].size(), 4u);
  // The first pair is the strongest overlap of all (A and B fly the same figure-eight).
  int best_agreeing = 0;
  for (const json& w : j["overlaps"]) best_agreeing = std::max(best_agreeing, w["agreeing_pairs"].get<int>());
  for (const json& w : j["overlaps"])
    if (w["agreeing_pairs"] == best_agreeing) {
      EXPECT_EQ(j["order"][0], w["runs"][0]);
      EXPECT_EQ(j["order"][1], w["runs"][1]);
      break;
    }
  for (const json& w : j["overlaps"]) {
    if (w["runs"][0] == 2 || w["runs"][1] == 2) {
      EXPECT_FALSE(w["placed"].get<bool>()) << w.dump();
    }
  }
  // One SLAM map holding every office run's keyframes.
  EXPECT_EQ(keyframes_of(o.out_dir), n_keyframes);
}

TEST(MergeMany, CommandLineMergesThreeRunsAndSaysHowEachJoined) {
  const fs::path out = scratch_dir() / "merge_cli";
  // An earlier merge of more runs left its 7th trajectory; the user keeps notes beside it.
  fs::remove_all(out);
  fs::create_directories(out);
  std::ofstream(out / "trajectory_camera_7.txt") << "# an earlier merge's\n";
  std::ofstream(out / "notes.txt") << "mine";
  std::string log;
  ASSERT_EQ(
      run_s3m("merge '" + fleet_run("a") + "' '" + fleet_run("b") + "' '" + fleet_run("handheld") +
                  "' --config '" + S3M_TEST_DATA_DIR + "/../../config/sim.yaml' --out '" + out.string() + "'",
              scratch_dir() / "merge_cli.log", &log),
      0)
      << log;
  EXPECT_NE(log.find("run 1 (" + fleet_run("a") + "): world"), std::string::npos) << log;
  EXPECT_NE(log.find("run 2 (" + fleet_run("b") + "): joined through run 1, "), std::string::npos) << log;
  EXPECT_NE(log.find("run 3 (" + fleet_run("handheld") + "): joined through run "), std::string::npos) << log;
  const json j = json::parse(read_bytes((out / "merge.json").string()));
  EXPECT_EQ(j["order"], json({1, 2, 3}));
  for (const char* f : {"slam_map.bin", "kept_clouds.bin", "map.ot", "trajectory_camera_3.txt"})
    EXPECT_TRUE(fs::exists(out / f)) << f;
  EXPECT_FALSE(fs::exists(out / "trajectory_camera_7.txt"));  // not this merge's: removed
  EXPECT_EQ(read_bytes((out / "notes.txt").string()), "mine");
  for (const auto& e : fs::directory_iterator(out))
    EXPECT_NE(e.path().filename().string().rfind(".s3m-staging", 0), 0u) << e.path();
}

TEST(MergeMany, RefusesTooFewOrRepeatedRunsAndForeignFolders) {
  run::MergeManyOptions o;
  o.config = sim_preset();
  o.out_dir = (scratch_dir() / "merge_refused").string();
  auto error_of = [&](std::vector<std::string> runs) -> std::string {
    o.runs = std::move(runs);
    try {
      run::merge_many(o);
    } catch (const Error& e) {
      return e.what();
    }
    return "";
  };
  EXPECT_NE(error_of({fleet_run("a")}).find("at least two runs"), std::string::npos);
  EXPECT_NE(error_of({fleet_run("a"), fleet_run("b"), fleet_run("a")})
                .find("run 3 '" + fleet_run("a") + "' is run 1"),
            std::string::npos);
  const std::string e = error_of({fleet_run("a"), fleet_run("b"), (scratch_dir() / "nowhere").string()});
  EXPECT_NE(e.find("run 3"), std::string::npos) << e;
  EXPECT_NE(e.find("is not a folder"), std::string::npos) << e;
  o.out_dir = fleet_run("b");
  EXPECT_NE(error_of({fleet_run("a"), fleet_run("b"), fleet_run("handheld")}).find("is one of the runs"),
            std::string::npos);
  EXPECT_FALSE(fs::exists(scratch_dir() / "merge_refused"));
}

}  // namespace
}  // namespace s3m::it
