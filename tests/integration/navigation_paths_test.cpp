// Paths on maps s3m built with SLAM poses from simulated flights, checked against the simulator's
// ground truth (issue's verification): random start / goal-class pairs (fixed seeds) in three
// scenes; every returned path keeps the robot radius from the ground-truth voxels at every
// centimetre, paths are found where the ground-truth map has one, and they are not much longer
// than the ground-truth optimum (Dijkstra on the ground-truth grid dilated by the radius).
#include <cstdio>
#include <filesystem>
#include <random>

#include <gtest/gtest.h>

#include "s3m/core/error.hpp"
#include "s3m/io/trajectory.hpp"
#include "s3m/mapping/map_io.hpp"
#include "s3m/navigation/goals.hpp"
#include "s3m/navigation/planner.hpp"
#include "s3m/pipeline/pipeline_config.hpp"
#include "s3m/run/evaluation.hpp"
#include "s3m/run/run.hpp"
#include "s3m/sim/simulate.hpp"

#include "cached_folder.hpp"
#include "navigation_gt_grid.hpp"

namespace s3m::it {
namespace {
namespace fs = std::filesystem;

constexpr double kRadius = 0.3, kNear = 0.5;
constexpr int kPairsPerScene = 17;  // 51 in all
const std::vector<ClassId> kGoalClasses = {cls::kBed,       cls::kSofa,  cls::kTable, cls::kChair,
                                           cls::kCabinet,   cls::kShelf, cls::kPlant, cls::kPerson,
                                           cls::kTvMonitor, cls::kDoor};

sim::SimConfig flight(const std::string& scene) {
  sim::SimConfig c;
  c.scene = scene;
  c.seed = 3;
  // Round a room looking outwards, or down a corridor and back looking along it: most of it is seen.
  c.trajectory.type = scene == "corridor" ? "forward" : "loop";
  c.trajectory.frames = 150;
  return c;
}

// The flight rendered once and the map s3m built from it with SLAM poses, both cached.
std::pair<std::string, std::string> sequence_and_run(const std::string& scene) {
  const auto tmpdir = fs::temp_directory_path();
  const std::string seq = cached_folder(
      tmpdir / ("s3m_it_nav_" + scene + "_" + flight(scene).trajectory.type + "_s3_150"), "gt_voxels.txt",
      [&](const fs::path& tmp) { sim::simulate_sequence(flight(scene), tmp.string()); });
  const std::string out = cached_folder(
      build_stamped(tmpdir / ("s3m_it_nav_run_" + scene + "_" + flight(scene).trajectory.type)), "map.ot",
      [&](const fs::path& tmp) {
        run::RunOptions o;
        o.dataset_dir = seq;
        o.out_dir = tmp.string();
        o.config = pipeline::load_pipeline_config(std::string(S3M_TEST_DATA_DIR) + "/../../config/sim.yaml");
        o.config.threads.deterministic = true;
        o.segmenter = "oracle";
        o.report = false;
        run::run_dataset(o);
      });
  return {seq, out};
}

// The ground truth's world in the map's frame, from the matched camera poses.
SE3 map_from_gt(const std::string& seq, const std::string& out) {
  const auto est = io::read_tum_trajectory(out + "/trajectory_camera.txt");
  const auto gt = io::read_tum_trajectory(seq + "/groundtruth.txt");
  std::vector<SE3> a, b;
  for (const auto& e : est)
    for (const auto& g : gt)
      if (std::abs(e.t_s - g.t_s) < 1e-4) a.push_back(e.T_w_x), b.push_back(g.T_w_x);
  return run::align_poses(a, b);
}

struct Tally {
  int pairs = 0, gt_reachable = 0, found = 0, found_reachable = 0, unsafe_paths = 0, long_paths = 0;
  int seen_reachable = 0, found_seen_reachable = 0;
  double worst_ratio = 0.0, ratio_sum = 0.0, min_gt_clearance = 1e9;
};

void check_scene(const std::string& scene, Tally& total) {
  const auto [seq, out] = sequence_and_run(scene);
  auto tree = mapping::load_semantic_map(out + "/map.ot");
  const navigation::DistanceField field(*tree);
  const SE3 T_gt_map = map_from_gt(seq, out).inverse();
  const GtGrid gt(io::read_gt_voxels(seq + "/gt_voxels.txt"), 0.2);
  const auto gt_dist = gt.distance_to_voxels();
  // Free for the robot in the ground truth; and the same where the flight looked, the robot's
  // whole sphere included: a map cannot know a way through space nobody saw.
  const SE3 T_map_gt = T_gt_map.inverse();
  std::vector<std::uint8_t> gt_free(gt.cells()), gt_free_seen(gt.cells()), unseen(gt.cells());
  for (std::size_t i = 0; i < gt.cells(); ++i) {
    gt_free[i] = gt_dist[i] >= kRadius;
    const Eigen::Vector3d p = T_map_gt * gt.centre(gt.cell(i));
    unseen[i] = tree->search(p.x(), p.y(), p.z()) == nullptr;
  }
  // Every unknown voxel of the map marks its ground-truth cell too (the grids are rotated against
  // each other: cell centres alone step over single voxels).
  const Eigen::Vector3i box =
      ((field.max_w() - field.min_w()) / field.resolution()).array().round().cast<int>();
  for (int z = 0; z <= box.z(); ++z)
    for (int y = 0; y <= box.y(); ++y)
      for (int x = 0; x <= box.x(); ++x) {
        const Eigen::Vector3d p = field.min_w() + field.resolution() * Eigen::Vector3d(x, y, z);
        if (tree->search(p.x(), p.y(), p.z()) != nullptr) continue;
        if (const Eigen::Vector3i c = gt.cell_of(T_gt_map * p); gt.inside(c)) unseen[gt.index(c)] = 1;
      }
  const auto unseen_dist = gt.distance_to(unseen);
  // Unseen space keeps the distance the planner keeps from it (radius + margin), as in the map.
  navigation::PlannerConfig pc;
  pc.radius_m = kRadius;
  const double from_unseen = navigation::required_clearance(field, pc);
  for (std::size_t i = 0; i < gt.cells(); ++i) gt_free_seen[i] = gt_free[i] && unseen_dist[i] >= from_unseen;
  navigation::ClassGoalConfig gc;
  gc.near_m = kNear;
  gc.clearance_m = navigation::required_clearance(field, pc);
  // Goal classes the built map and the ground truth both hold.
  std::vector<ClassId> classes;
  for (const ClassId c : kGoalClasses)
    if (gt.has_class(c) && !mapping::object_instances(*tree, c, gc.min_voxels).empty()) classes.push_back(c);
  ASSERT_FALSE(classes.empty()) << scene;
  // Ground-truth path length to the class per cell: through all free space, through the seen part.
  std::map<ClassId, std::vector<float>> to_class, to_class_seen;
  std::mt19937 rng(std::hash<std::string>{}(scene)&0xffff);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  Tally t;
  while (t.pairs < kPairsPerScene) {
    // A start in space the map has seen free, also free in the ground truth.
    const Eigen::Vector3d s =
        field.min_w() + (field.max_w() - field.min_w()).cwiseProduct(Eigen::Vector3d(u(rng), u(rng), u(rng)));
    const Eigen::Vector3i s_cell = gt.cell_of(T_gt_map * s);
    if (field.clearance(s) < gc.clearance_m || !gt.inside(s_cell) || !gt_free[gt.index(s_cell)]) continue;
    const ClassId cls_id = classes[std::size_t(u(rng) * classes.size()) % classes.size()];
    ++t.pairs;
    if (!to_class.count(cls_id)) {
      const auto near = gt.distance_to_class(cls_id);
      std::vector<std::uint8_t> goal(gt.cells());
      for (std::size_t i = 0; i < gt.cells(); ++i) goal[i] = near[i] <= kNear;
      to_class[cls_id] = gt.path_lengths(gt_free, goal);
      to_class_seen[cls_id] = gt.path_lengths(gt_free_seen, goal);
    }
    const double optimum = to_class[cls_id][gt.index(s_cell)];
    const double optimum_seen = to_class_seen[cls_id][gt.index(s_cell)];
    const bool reachable = std::isfinite(optimum), seen_reachable = std::isfinite(optimum_seen);
    t.gt_reachable += reachable;
    t.seen_reachable += seen_reachable;
    navigation::Path path;
    try {
      const auto goal = navigation::class_goal(field, cls_id, s, gc);
      path = navigation::plan_path(field, s, goal.goals_w, pc);
    } catch (const Error& e) {
      std::printf("  %s: no path to %s from (%.2f %.2f %.2f)%s: %s\n", scene.c_str(),
                  tree->classes().at(cls_id).name.c_str(), s.x(), s.y(), s.z(),
                  seen_reachable ? " (the GT has one in seen space)"
                  : reachable    ? " (the GT has one through unseen space)"
                                 : "",
                  e.what());
      continue;
    }
    ++t.found;
    t.found_reachable += reachable;
    t.found_seen_reachable += seen_reachable;
    // Every centimetre of it, in the ground truth's frame.
    double lowest = 1e9;
    for (std::size_t i = 1; i < path.waypoints_w.size(); ++i) {
      const Eigen::Vector3d a = T_gt_map * path.waypoints_w[i - 1], b = T_gt_map * path.waypoints_w[i];
      const int n = std::max(1, int(std::ceil((b - a).norm() / 0.01)));
      for (int k = 0; k <= n; ++k)
        lowest = std::min(lowest, gt.clearance(a + (b - a) * (double(k) / n), 1.0));
    }
    t.min_gt_clearance = std::min(t.min_gt_clearance, lowest);
    t.unsafe_paths += lowest < kRadius;
    if (seen_reachable) {
      const double ratio = path.length_m / std::max(optimum_seen, 1e-3);
      t.worst_ratio = std::max(t.worst_ratio, ratio);
      t.ratio_sum += ratio;
      t.long_paths += ratio > 1.2 && path.length_m > optimum_seen + 0.1;  // slack for paths of a few voxels
      if (ratio > 1.2)
        std::printf(
            "  %s: path from (%.2f %.2f %.2f) to %s %.2f m, GT optimum %.2f m (%.2f m through unseen "
            "space)\n",
            scene.c_str(), s.x(), s.y(), s.z(), tree->classes().at(cls_id).name.c_str(), path.length_m,
            optimum_seen, optimum);
    }
  }
  std::printf(
      "%-12s pairs %d, GT reachable %d (%d in seen space), found %d (%d of the reachable, %d in seen space), "
      "unsafe %d, worst GT clearance %.3f m, length / optimum: mean %.3f, worst %.3f, > 1.2: %d\n",
      scene.c_str(), t.pairs, t.gt_reachable, t.seen_reachable, t.found, t.found_reachable,
      t.found_seen_reachable, t.unsafe_paths, t.min_gt_clearance,
      t.ratio_sum / std::max(1, t.found_seen_reachable), t.worst_ratio, t.long_paths);
  total.pairs += t.pairs, total.gt_reachable += t.gt_reachable, total.found += t.found;
  total.found_reachable += t.found_reachable, total.unsafe_paths += t.unsafe_paths,
      total.long_paths += t.long_paths;
  total.seen_reachable += t.seen_reachable, total.found_seen_reachable += t.found_seen_reachable;
  total.worst_ratio = std::max(total.worst_ratio, t.worst_ratio);
  total.min_gt_clearance = std::min(total.min_gt_clearance, t.min_gt_clearance);
}

}  // namespace

TEST(NavigationPaths, SafeFoundAndShortAgainstGroundTruthInThreeScenes) {
  Tally total;
  for (const std::string scene : {"office", "living_room", "corridor"}) {
    SCOPED_TRACE(scene);
    check_scene(scene, total);
    if (HasFatalFailure()) return;
  }
  EXPECT_GE(total.pairs, 50);
  EXPECT_EQ(total.unsafe_paths, 0) << "worst ground-truth clearance " << total.min_gt_clearance << " m";
  // Found where the ground truth has a path through the space the flight saw; the share of all
  // pairs the ground truth can reach (through unseen space too) is printed above.
  EXPECT_GE(total.found_seen_reachable, 0.95 * total.seen_reachable);
  EXPECT_GE(total.found_reachable, 0.95 * total.gt_reachable);  // these flights see enough for that
  std::printf(
      "all scenes: %d pairs, %d found; %d of %d GT-reachable (%d of %d reachable through seen space)\n",
      total.pairs, total.found, total.found_reachable, total.gt_reachable, total.found_seen_reachable,
      total.seen_reachable);
  // Length: within 1.2 x the optimum through the seen ground-truth space for 95 % of the paths. The
  // rest are cases where the map's unknown space, kept at radius + margin, narrows the direct way
  // more than the ground-truth model of the seen space (sampled on a rotated 5 cm grid) shows.
  EXPECT_LE(total.long_paths, 0.05 * total.found_seen_reachable)
      << "worst length / optimum " << total.worst_ratio;
}

}  // namespace s3m::it
