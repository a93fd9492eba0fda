// Paths on a hand-built map with a known answer: two rooms joined by a door in a wall, a bed in
// the far room. The path must keep the clearance from every obstacle voxel, go through the door,
// be close to the shortest, repeat with the same seed, and fail with the reason when it must.
#include <cmath>
#include <filesystem>
#include <fstream>

#include <gtest/gtest.h>

#include "s3m/core/error.hpp"
#include "s3m/navigation/goals.hpp"
#include "s3m/navigation/path_io.hpp"
#include "s3m/navigation/planner.hpp"
#include "s3m/navigation/reachability.hpp"

using namespace s3m;
using namespace s3m::navigation;

namespace {
constexpr double kRes = 0.1;

struct World {
  mapping::SemanticOcTree tree{kRes};
  std::vector<Eigen::Vector3d> obstacles;  // centres of the occupied voxels
};

// 4 x 2 x 1.5 m of observed space (voxels x 0..39, y 0..19, z 0..14); a wall at x = 2.05 m with a
// 0.8 m wide door (y 0.6..1.4) unless closed; a bed block x 3.0..3.5, y 0..0.5, z 0..0.4.
std::unique_ptr<World> world(bool door_open = true) {
  auto w = std::make_unique<World>();
  for (int x = 0; x < 40; ++x)
    for (int y = 0; y < 20; ++y)
      for (int z = 0; z < 15; ++z) {
        const bool wall = x == 20 && !(door_open && y >= 6 && y < 14);
        const bool bed = x >= 30 && x < 35 && y < 5 && z < 4;
        const Eigen::Vector3d c = (Eigen::Vector3d(x, y, z) + Eigen::Vector3d::Constant(0.5)) * kRes;
        const auto key = w->tree.coordToKey(c.x(), c.y(), c.z());
        w->tree.updateNode(key, wall || bed ? 2.0f : -2.0f);
        if (wall || bed) w->obstacles.push_back(c);
        if (bed) {
          mapping::LabelSet l;
          l.push(cls::kBed, 0.9f);
          w->tree.integrateObservation(key, l, {200, 100, 50});
        }
      }
  w->tree.updateInnerOccupancy();
  return w;
}

double gt_clearance(const World& w, const Eigen::Vector3d& p) {
  double d = 1e9;
  for (const auto& o : w.obstacles) d = std::min(d, (p - o).norm());
  return d;
}

}  // namespace

TEST(NavigationPlanner, ThroughTheDoorWithClearanceNearShortest) {
  auto w = world();
  const DistanceField field(w->tree);
  PlannerConfig cfg;
  cfg.radius_m = 0.2;
  const Eigen::Vector3d start(0.5, 1.0, 0.7), goal(3.5, 1.0, 0.7);
  const Path path = plan_path(field, start, {goal}, cfg);
  ASSERT_GE(path.waypoints_w.size(), 2u);
  EXPECT_TRUE(path.waypoints_w.front().isApprox(start));
  EXPECT_TRUE(path.waypoints_w.back().isApprox(goal));
  // Every centimetre keeps the radius from every obstacle voxel centre.
  for (std::size_t i = 1; i < path.waypoints_w.size(); ++i) {
    const Eigen::Vector3d a = path.waypoints_w[i - 1], d = path.waypoints_w[i] - a;
    for (double s = 0.0; s <= 1.0; s += 0.01 / std::max(d.norm(), 0.01))
      ASSERT_GE(gt_clearance(*w, a + s * d), cfg.radius_m) << "at " << (a + s * d).transpose();
  }
  // The straight line goes through the door: the path should be about as short.
  EXPECT_LE(path.length_m, 1.1 * (goal - start).norm());
  EXPECT_NEAR(path.length_m, path_length(path.waypoints_w), 1e-9);
  EXPECT_GE(path.min_clearance_m, required_clearance(field, cfg) - 1e-9);
  // Same seed, same path.
  const Path again = plan_path(field, start, {goal}, cfg);
  ASSERT_EQ(again.waypoints_w.size(), path.waypoints_w.size());
  for (std::size_t i = 0; i < path.waypoints_w.size(); ++i)
    EXPECT_TRUE(again.waypoints_w[i].isApprox(path.waypoints_w[i]));
}

TEST(NavigationPlanner, ReasonsWhenThereIsNoPath) {
  auto w = world(/*door_open=*/false);
  const DistanceField field(w->tree);
  PlannerConfig cfg;
  cfg.radius_m = 0.2;
  cfg.time_limit_s = 0.2;
  cfg.attempts = 1;
  const auto message = [&](const Eigen::Vector3d& s, const Eigen::Vector3d& g) {
    try {
      plan_path(field, s, {g}, cfg);
    } catch (const Error& e) {
      return std::string(e.what());
    }
    return std::string("no error");
  };
  EXPECT_NE(message({0.5, 1.0, 0.7}, {3.5, 1.0, 0.7}).find("is connected to the start"), std::string::npos);
  EXPECT_NE(message({2.05, 1.0, 0.7}, {3.5, 1.0, 0.7}).find("inside an obstacle"), std::string::npos);
  EXPECT_NE(message({1.9, 1.0, 0.7}, {0.5, 1.0, 0.7}).find("too close"), std::string::npos);
  EXPECT_NE(message({9.0, 1.0, 0.7}, {0.5, 1.0, 0.7}).find("outside the map"), std::string::npos);
  EXPECT_NE(message({0.5, 1.0, 0.7}, {0.5, 1.0, 1.48}).find("goal"), std::string::npos);
}

TEST(NavigationReachability, GridLengthsThroughTheDoorAndNoneWhenClosed) {
  auto open = world();
  const DistanceField field(open->tree);
  // Straight through the door: 30 axis steps of 10 cm.
  const auto r = grid_reachability(field, {0.55, 1.05, 0.75}, {{3.55, 1.05, 0.75}, {1.05, 1.05, 0.75}}, 0.3);
  EXPECT_NEAR(r.lengths_m[0], 3.0, 1e-5);
  EXPECT_NEAR(r.lengths_m[1], 0.5, 1e-5);
  auto closed = world(/*door_open=*/false);
  const DistanceField field2(closed->tree);
  const auto r2 =
      grid_reachability(field2, {0.55, 1.05, 0.75}, {{3.55, 1.05, 0.75}, {1.05, 1.05, 0.75}}, 0.3);
  EXPECT_TRUE(std::isinf(r2.lengths_m[0]));
  EXPECT_NEAR(r2.lengths_m[1], 0.5, 1e-5);
  // The start's side of the wall: x 0..1.95 minus 0.3 m clearance all round, at 10 cm voxels.
  EXPECT_GT(r2.voxels_reached, 100u);
  EXPECT_LT(r2.voxels_reached, 20u * 20u * 15u);
}

TEST(NavigationGoals, NearTheNearestBedAndAbsentClassesListed) {
  auto w = world();
  const DistanceField field(w->tree);
  ClassGoalConfig cfg;
  cfg.near_m = 0.5;
  cfg.clearance_m = 0.3;
  const auto goal = class_goal(field, cls::kBed, {0.5, 1.0, 0.7}, cfg);
  ASSERT_EQ(goal.instances.size(), 1u);
  EXPECT_EQ(goal.instances[0].voxels, 100u);
  EXPECT_EQ(goal.goal_instance.size(), goal.goals_w.size());
  ASSERT_FALSE(goal.goals_w.empty());
  for (const auto& g : goal.goals_w) {
    // Within near_m of the bed's box (x 3.0..3.5, y 0..0.5, z 0..0.4) and with the clearance.
    const Eigen::Vector3d lo(3.0, 0.0, 0.0), hi(3.5, 0.5, 0.4);
    EXPECT_LE((lo - g).cwiseMax(g - hi).cwiseMax(0.0).norm(), cfg.near_m + 1e-9) << g.transpose();
    EXPECT_GE(field.clearance(g), cfg.clearance_m);
  }
  for (std::size_t i = 1; i < goal.goals_w.size(); ++i)  // nearest to the start first
    EXPECT_LE((goal.goals_w[i - 1] - Eigen::Vector3d(0.5, 1.0, 0.7)).norm(),
              (goal.goals_w[i] - Eigen::Vector3d(0.5, 1.0, 0.7)).norm() + 1e-9);
  try {
    class_goal(field, cls::kChair, {0.5, 1.0, 0.7}, cfg);
    FAIL() << "a chair was found";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("no chair"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("bed (1 instance)"), std::string::npos) << e.what();
  }
}

TEST(NavigationPathIo, TumPosesWithArcLengthTimes) {
  const std::string file =
      (std::filesystem::temp_directory_path() / ("s3m_nav_tum_" + std::to_string(::getpid()))).string();
  write_path_tum(file, {{0, 0, 1}, {1, 0, 1}, {1, 2, 1}});
  std::ifstream in(file);
  std::string header;
  std::getline(in, header);
  double t, x, y, z, qx, qy, qz, qw;
  std::vector<double> times, yaws;
  while (in >> t >> x >> y >> z >> qx >> qy >> qz >> qw)
    times.push_back(t), yaws.push_back(2 * std::atan2(qz, qw));
  ASSERT_EQ(times.size(), 3u);
  EXPECT_NEAR(times[1], 1.0, 1e-6);
  EXPECT_NEAR(times[2], 3.0, 1e-6);
  EXPECT_NEAR(yaws[0], 0.0, 1e-6);
  EXPECT_NEAR(yaws[1], M_PI / 2, 1e-6);
  EXPECT_NEAR(yaws[2], M_PI / 2, 1e-6);
  std::filesystem::remove(file);
}
