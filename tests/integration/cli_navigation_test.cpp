// `s3m plan`, `s3m query --clearance` and `s3m export --costmap` as a user runs them, on a small
// hand-built map (two rooms joined by a door, a bed in the far one): outputs and error messages.
#include <filesystem>
#include <fstream>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "s3m/mapping/map_io.hpp"

#include "pipeline_fixture.hpp"

namespace s3m::it {
namespace {

const auto* const kCleanup = ::testing::AddGlobalTestEnvironment(new ScratchCleanup);

// 4 x 2 x 1.5 m observed at 10 cm; a wall at x = 2.05 m with a door at y 0.6..1.4; a bed block at
// x 3.0..3.5, y 0..0.5, z 0..0.4.
std::string two_rooms_map() {
  static const std::string path = [] {
    mapping::SemanticOcTree t(0.1);
    for (int x = 0; x < 40; ++x)
      for (int y = 0; y < 20; ++y)
        for (int z = 0; z < 15; ++z) {
          const bool wall = x == 20 && !(y >= 6 && y < 14), bed = x >= 30 && x < 35 && y < 5 && z < 4;
          const auto key = t.coordToKey((x + 0.5) * 0.1, (y + 0.5) * 0.1, (z + 0.5) * 0.1);
          t.updateNode(key, wall || bed ? 2.0f : -2.0f);
          if (bed) {
            mapping::LabelSet l;
            l.push(cls::kBed, 0.9f);
            t.integrateObservation(key, l, {200, 100, 50});
          }
        }
    t.updateInnerOccupancy();
    const std::string p = (scratch_dir() / "two_rooms.ot").string();
    mapping::save_semantic_map(t, p);
    return p;
  }();
  return path;
}

std::string s3m(const std::string& args, int* status) {
  std::string log;
  *status = run_s3m(args, scratch_dir() / "nav_cli.log", &log);
  return log;
}

}  // namespace

TEST(CliNavigation, PlanToTheBedWritesJsonAndTum) {
  const auto json = scratch_dir() / "path.json", tum = scratch_dir() / "path.txt";
  int status = 0;
  const auto log = s3m("plan " + two_rooms_map() + " --from 0.5,1.0,0.7 --to-class bed --radius 0.2 --out " +
                           json.string() + " --tum " + tum.string(),
                       &status);
  ASSERT_EQ(status, 0) << log;
  const auto j = nlohmann::json::parse(std::ifstream(json));
  ASSERT_GE(j["waypoints_m"].size(), 2u);
  EXPECT_EQ(j["class"], "bed");
  EXPECT_GE(j["min_clearance_m"].get<double>(), 0.3 - 1e-9);  // radius + one voxel
  const auto to = j["to"];
  EXPECT_GT(to[0].get<double>(), 2.4);  // through the door, in the bed's room
  EXPECT_GT(j["length_m"].get<double>(), 2.0);
  std::ifstream t(tum);
  std::string header, line;
  std::getline(t, header);
  int poses = 0;
  while (std::getline(t, line)) ++poses;
  EXPECT_EQ(poses, int(j["waypoints_m"].size()));
}

TEST(CliNavigation, ClearErrors) {
  int status = 0;
  auto log = s3m("plan " + two_rooms_map() + " --from 2.05,0.3,0.7 --to-class bed", &status);
  EXPECT_EQ(status, 1);
  EXPECT_NE(log.find("inside an obstacle"), std::string::npos) << log;
  log = s3m("plan " + two_rooms_map() + " --from 0.5,1.0,0.7 --to-class chair", &status);
  EXPECT_EQ(status, 1);
  EXPECT_NE(log.find("no chair"), std::string::npos) << log;
  EXPECT_NE(log.find("bed (1 instance)"), std::string::npos) << log;
  log = s3m("plan " + two_rooms_map() + " --from 0.5,1.0,0.7 --to-class unicorn", &status);
  EXPECT_NE(log.find("unknown class 'unicorn'"), std::string::npos) << log;
  log = s3m("plan " + two_rooms_map() + " --from 0.5,1.0,0.7 --to-class bed --to 1,1,1", &status);
  EXPECT_NE(log.find("exactly one of"), std::string::npos) << log;
}

TEST(CliNavigation, ClearanceAndCostmap) {
  int status = 0;
  auto log = s3m("query " + two_rooms_map() + " --clearance 1.55,0.45,0.75 --json", &status);
  ASSERT_EQ(status, 0) << log;
  EXPECT_NEAR(nlohmann::json::parse(log)["clearance"]["clearance_m"].get<double>(), 0.5,
              1e-5);  // to the wall and to the unknown beyond y = 0
  const auto yaml = scratch_dir() / "rooms.yaml";
  log =
      s3m("export " + two_rooms_map() + " --costmap " + yaml.string() + " --min-z 0.3 --max-z 1.2", &status);
  ASSERT_EQ(status, 0) << log;
  EXPECT_TRUE(std::filesystem::exists(scratch_dir() / "rooms.pgm"));
  std::ifstream pgm(scratch_dir() / "rooms.pgm", std::ios::binary);
  std::string magic, comment;
  int w = 0, h = 0;
  pgm >> magic;
  pgm.ignore(1);
  std::getline(pgm, comment);
  pgm >> w >> h;
  EXPECT_EQ(magic, "P5");
  EXPECT_EQ(w, 40);
  EXPECT_EQ(h, 20);
}

}  // namespace s3m::it
