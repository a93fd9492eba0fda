// Merging sessions (issue 23), end to end through run_dataset and merge_runs on two flights of one
// simulated office (session_sim_fixture.hpp): flight A (the figure-eight, which always looks
// towards one end of the room) is the saved session; flight C takes off at the other end looking
// the other way, where A never looked, and turns round during its flight into A's view. `s3m run
// C --map A` cannot relocalise at its start, starts a sub-map, and merges it into A's map when
// place recognition finds it: one map in A's world, whose semantic map scores at least the better
// single run's mIoU against the simulator's voxels and covers what both runs covered.
// `s3m merge A C` does the same offline; runs that cannot be merged say why.
#include <array>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <map>
#include <set>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "pipeline_fixture.hpp"
#include "s3m/core/classes.hpp"
#include "s3m/core/error.hpp"
#include "s3m/features/bow_vocabulary.hpp"
#include "s3m/io/gt_voxels.hpp"
#include "s3m/io/trajectory.hpp"
#include "s3m/io/tum_dataset.hpp"
#include "s3m/mapping/map_io.hpp"
#include "s3m/mapping/metrics.hpp"
#include "s3m/pipeline/session_io.hpp"
#include "s3m/run/evaluation.hpp"
#include "s3m/run/run.hpp"
#include "s3m/run/session_merge.hpp"
#include "s3m/slam/io/map_io.hpp"
#include "session_runs.hpp"

namespace s3m::it {
namespace {

using nlohmann::json;

json metrics(const std::string& run) { return json::parse(read_bytes(run + "/metrics.json")); }

// The ground-truth world in a run's world: whole-pose alignment of its trajectory to its dataset's.
SE3 T_run_gt(const std::string& run, const std::string& dataset) {
  const io::Trajectory est = io::read_tum_trajectory(run + "/trajectory_camera.txt");
  const io::Trajectory gt = io::read_tum_trajectory(dataset + "/groundtruth.txt");
  std::vector<SE3> e, g;
  for (const auto& p : est)
    for (const auto& q : gt)
      if (std::abs(p.t_s - q.t_s) < 1e-4) e.push_back(p.T_w_x), g.push_back(q.T_w_x);
  return run::align_poses(e, g);
}

double ate_m(const std::string& run, const std::string& dataset, const SE3& T_run_gt) {
  const io::Trajectory est = io::read_tum_trajectory(run + "/trajectory_camera.txt");
  const io::Trajectory gt = io::read_tum_trajectory(dataset + "/groundtruth.txt");
  double s = 0;
  int n = 0;
  for (const auto& p : est)
    for (const auto& q : gt)
      if (std::abs(p.t_s - q.t_s) < 1e-4)
        s += (T_run_gt.inverse() * p.T_w_x.translation() - q.T_w_x.translation()).squaredNorm(), ++n;
  return std::sqrt(s / std::max(n, 1));
}

// The ground-truth voxels (indices into gt_voxels.txt) a map has an occupied voxel at, within one
// voxel per axis (the tolerance of the map metrics, mapping::MapEvalConfig).
std::set<std::size_t> covered(const std::string& map_ot, const std::string& gt_path, const SE3& T_map_gt) {
  const auto tree = mapping::load_semantic_map(map_ot);
  const io::GtVoxelMap gt = io::read_gt_voxels(gt_path);
  const Eigen::Isometry3f T = T_map_gt.cast<float>();
  const float r = float(tree->getResolution());
  auto occupied = [&](const Eigen::Vector3f& c) {
    for (int dx = -1; dx <= 1; ++dx)
      for (int dy = -1; dy <= 1; ++dy)
        for (int dz = -1; dz <= 1; ++dz) {
          const auto* n = tree->search(c.x() + dx * r, c.y() + dy * r, c.z() + dz * r);
          if (n && tree->isNodeOccupied(n)) return true;
        }
    return false;
  };
  std::set<std::size_t> out;
  for (std::size_t i = 0; i < gt.centres_w.size(); ++i)
    if (occupied(T * gt.centres_w[i])) out.insert(i);
  return out;
}

// The ground-truth voxels whose cell a map knows (free or occupied: some camera saw it).
std::set<std::size_t> observed(const std::string& map_ot, const std::string& gt_path, const SE3& T_map_gt) {
  const auto tree = mapping::load_semantic_map(map_ot);
  const io::GtVoxelMap gt = io::read_gt_voxels(gt_path);
  const Eigen::Isometry3f T = T_map_gt.cast<float>();
  std::set<std::size_t> out;
  for (std::size_t i = 0; i < gt.centres_w.size(); ++i) {
    const Eigen::Vector3f c = T * gt.centres_w[i];
    if (tree->search(c.x(), c.y(), c.z())) out.insert(i);
  }
  return out;
}

// A map's mIoU (run::score_map's definition: over the ground-truth classes present) on a
// subset of the ground-truth voxels.
double miou_on(const std::string& map_ot, const std::string& gt_path, const SE3& T_map_gt,
               const std::set<std::size_t>& subset) {
  const auto tree = mapping::load_semantic_map(map_ot);
  const io::GtVoxelMap gt = io::read_gt_voxels(gt_path);
  io::GtVoxelMap sub;
  sub.resolution_m = gt.resolution_m;
  for (std::size_t i : subset) {
    sub.centres_w.push_back(T_map_gt.cast<float>() * gt.centres_w[i]);
    sub.labels.push_back(gt.labels[i]);
  }
  const mapping::MapEvaluation e = mapping::evaluate_map(*tree, sub);
  std::set<ClassId> classes(sub.labels.begin(), sub.labels.end());
  classes.erase(cls::kUnknown);
  double sum = 0;
  for (ClassId c : classes) sum += e.iou.count(c) ? e.iou.at(c) : 0.0;
  return classes.empty() ? 0.0 : sum / double(classes.size());
}

// The ground-truth voxels a flight's camera hit: every depth pixel the pipeline maps (the preset's
// stride and range), back-projected with the true pose, lands in one. A run's area as the sensor saw
// it, apart from any run's pose error and from the metric's one-voxel tolerance (which lets a map
// "cover" voxels next to a surface no camera saw).
std::set<std::size_t> hit_by_camera(const std::string& dataset, const std::string& gt_path) {
  const io::TumDataset d = io::TumDataset::open(dataset);
  const io::GtVoxelMap gt = io::read_gt_voxels(gt_path);
  auto key = [&](const Eigen::Vector3d& p) {
    return std::array<long, 3>{std::lround(std::floor(p.x() / gt.resolution_m)),
                               std::lround(std::floor(p.y() / gt.resolution_m)),
                               std::lround(std::floor(p.z() / gt.resolution_m))};
  };
  std::map<std::array<long, 3>, std::size_t> index;
  for (std::size_t i = 0; i < gt.centres_w.size(); ++i) index[key(gt.centres_w[i].cast<double>())] = i;
  const pipeline::CloudConfig cc = sim_preset().cloud;
  std::set<std::size_t> out;
  for (std::size_t f = 0; f < d.size(); ++f) {
    const cv::Mat depth = d.load(f).depth_m;
    const SE3 T_w_c = d.groundtruth_at(d.timestamp(f)).value();
    for (int v = 0; v < depth.rows; v += cc.pixel_stride)
      for (int u = 0; u < depth.cols; u += cc.pixel_stride) {
        const double z = depth.at<float>(v, u);
        if (z < cc.min_depth_m || z > cc.max_depth_m) continue;
        const auto it = index.find(key(T_w_c * d.camera().backproject(u, v, z)));
        if (it != index.end()) out.insert(it->second);
      }
  }
  return out;
}

// Whether run Y's own map holds free every cell near ground-truth voxel i that run X's map holds
// occupied (each map under its own alignment): the two sessions' evidence disagrees there, and a
// log-odds map of both follows the weight of it.
bool contradicted(const mapping::SemanticOcTree& x, const SE3& T_x_gt, const mapping::SemanticOcTree& y,
                  const SE3& T_y_gt, const Eigen::Vector3f& centre_gt) {
  const auto* tx = &x;
  const auto* ty = &y;
  const Eigen::Vector3f cx = T_x_gt.cast<float>() * centre_gt, cy = T_y_gt.cast<float>() * centre_gt;
  const float r = float(tx->getResolution());
  int occupied = 0, freed = 0;
  for (int dx = -1; dx <= 1; ++dx)
    for (int dy = -1; dy <= 1; ++dy)
      for (int dz = -1; dz <= 1; ++dz) {
        const Eigen::Vector3f o(dx * r, dy * r, dz * r);
        const auto* n = tx->search(cx.x() + o.x(), cx.y() + o.y(), cx.z() + o.z());
        if (!n || !tx->isNodeOccupied(n)) continue;
        ++occupied;
        const auto* m = ty->search(cy.x() + o.x(), cy.y() + o.y(), cy.z() + o.z());
        freed += m && !ty->isNodeOccupied(m);
      }
  return occupied > 0 && freed == occupied;
}

std::size_t union_size(const std::set<std::size_t>& a, const std::set<std::size_t>& b) {
  std::set<std::size_t> u = a;
  u.insert(b.begin(), b.end());
  return u.size();
}

TEST(MergeSession, FlightStartingOutsideTheMapEndsAsOneMap) {
  const json m = metrics(run_c_in_a());
  const json& sub = m["tracking"]["submaps"];
  std::printf("run C --map A: states %s, sub-maps %s\n", m["tracking"]["states"].dump().c_str(),
              sub.dump().c_str());
  EXPECT_EQ(sub.value("started", 0), 1) << "C starts outside A's map";
  EXPECT_EQ(sub.value("merges", 0), 1) << "and enters it";
  EXPECT_EQ(sub.value("keyframes_outside_world", -1), 0) << "one map at the end";
  EXPECT_GT(m["tracking"]["states"].value("SUBMAP", 0), 0);
  // Every frame from the sub-map's first on is in the trajectory, in A's world: judged with A's
  // alignment to the ground truth only.
  const int start = sim_preset().slam.loop_closing.loop.merge.start_frames;
  const io::Trajectory est = io::read_tum_trajectory(run_c_in_a() + "/trajectory_camera.txt");
  EXPECT_EQ(int(est.size()),
            flight_c_config().trajectory.frames - start + 1);  // the last failed frame starts the sub-map
  const SE3 T_a = T_run_gt(run_a(), flight_a_dir());
  const double ate_in_a = ate_m(run_c_in_a(), flight_c_dir(), T_a);
  std::printf("run C --map A: %zu poses, ATE with A's alignment %.4f m (run C alone, own alignment %.4f m)\n",
              est.size(), ate_in_a, ate_m(run_c(), flight_c_dir(), T_run_gt(run_c(), flight_c_dir())));
  // C keeps the drift it had on its own before the merge (one seam aligns, it cannot bend the
  // path), judged here without C's own best-fit alignment, plus the seam's own error (one SE3 from
  // 3D-3D matches) and A's: allow 1 cm more than C alone. Measured: 4.72 vs 4.30 cm before issue
  // 20's depth weighting, 2.55 vs 1.83 cm after it (C alone improved more than the seam).
  EXPECT_LE(ate_in_a, ate_m(run_c(), flight_c_dir(), T_run_gt(run_c(), flight_c_dir())) + 0.01);
  // The saved session holds A's keyframes and C's.
  const auto vocab = std::make_shared<const features::Vocabulary>(
      features::Vocabulary::load(features::default_vocabulary_path()));
  const int n_a = slam::load_slam_map(run_a() + "/slam_map.bin", vocab).map.n_keyframes();
  const int n_merged = slam::load_slam_map(run_c_in_a() + "/slam_map.bin", vocab).map.n_keyframes();
  EXPECT_GT(n_merged, n_a);
}

// The semantic maps against the simulator's voxels. Each run's own map mIoU (metrics.json) is over
// the ground truth that map observed; the merged map observes more (both areas), so the fair
// comparison is on the same voxels: everything either run observed, and each run's own area.
struct MapComparison {
  double own_a, own_c, own_merged;        // metrics.json map.miou (each over its own observed space)
  double union_a, union_c, union_merged;  // on the voxels either run observed
  double a_on_a, merged_on_a, c_on_c, merged_on_c;  // on each run's own observed voxels
  std::size_t covered_a, covered_c, covered_union, covered_merged;
  // On the voxels a camera hit: covered by A or C, by the merged map, and what the merged map
  // misses of the union, split into voxels the other run's own map holds free and the rest.
  std::size_t hit_union, hit_merged, missed_contradicted, missed_other;
};

MapComparison compare_maps(const std::string& merged_ot, const SE3& T_merged_gt, double own_merged) {
  const std::string gt = flight_a_dir() + "/gt_voxels.txt";  // one building: the same voxels
  const SE3 T_a = T_run_gt(run_a(), flight_a_dir()), T_c = T_run_gt(run_c(), flight_c_dir());
  const std::string a_ot = run_a() + "/map.ot", c_ot = run_c() + "/map.ot";
  const auto seen_a = observed(a_ot, gt, T_a), seen_c = observed(c_ot, gt, T_c);
  std::set<std::size_t> seen = seen_a;
  seen.insert(seen_c.begin(), seen_c.end());
  const auto ca = covered(a_ot, gt, T_a), cc = covered(c_ot, gt, T_c),
             cm = covered(merged_ot, gt, T_merged_gt);
  MapComparison m{metrics(run_a())["map"]["miou"],
                  metrics(run_c())["map"]["miou"],
                  own_merged,
                  miou_on(a_ot, gt, T_a, seen),
                  miou_on(c_ot, gt, T_c, seen),
                  miou_on(merged_ot, gt, T_merged_gt, seen),
                  miou_on(a_ot, gt, T_a, seen_a),
                  miou_on(merged_ot, gt, T_merged_gt, seen_a),
                  miou_on(c_ot, gt, T_c, seen_c),
                  miou_on(merged_ot, gt, T_merged_gt, seen_c),
                  ca.size(),
                  cc.size(),
                  union_size(ca, cc),
                  cm.size(),
                  0,
                  0,
                  0,
                  0};
  std::set<std::size_t> hit = hit_by_camera(flight_a_dir(), gt);
  for (std::size_t i : hit_by_camera(flight_c_dir(), gt)) hit.insert(i);
  const io::GtVoxelMap voxels = io::read_gt_voxels(gt);
  const auto tree_a = mapping::load_semantic_map(a_ot), tree_c = mapping::load_semantic_map(c_ot);
  for (std::size_t i : hit) {
    const bool in_a = ca.count(i), in_c = cc.count(i);
    if (!in_a && !in_c) continue;
    ++m.hit_union;
    if (cm.count(i)) {
      ++m.hit_merged;
      continue;
    }
    const Eigen::Vector3f& g = voxels.centres_w[i];
    const bool explained = (!in_a || contradicted(*tree_a, T_a, *tree_c, T_c, g)) &&
                           (!in_c || contradicted(*tree_c, T_c, *tree_a, T_a, g));
    ++(explained ? m.missed_contradicted : m.missed_other);
  }
  std::printf(
      "  map mIoU, own observed space: A %.4f, C %.4f, merged %.4f\n"
      "  on the voxels either run observed (%zu): A %.4f, C %.4f, merged %.4f\n"
      "  where A looked: A %.4f, merged %.4f; where C looked: C %.4f, merged %.4f\n"
      "  ground-truth voxels covered (1-voxel tolerance): A %zu, C %zu, union %zu, merged %zu\n",
      m.own_a, m.own_c, m.own_merged, seen.size(), m.union_a, m.union_c, m.union_merged, m.a_on_a,
      m.merged_on_a, m.c_on_c, m.merged_on_c, m.covered_a, m.covered_c, m.covered_union, m.covered_merged);
  std::printf(
      "  of the voxels a camera hit (%zu): union %zu, merged %zu; the merged map misses %zu of the union, "
      "%zu where the other run's own map holds them free, %zu otherwise\n",
      hit.size(), m.hit_union, m.hit_merged, m.hit_union - m.hit_merged, m.missed_contradicted,
      m.missed_other);
  return m;
}

// Issue 23 asks for the merged map's mIoU >= the better single run's and coverage >= the union.
// The merged map lives in A's world, so A's alignment to the ground truth scores it, online as
// offline (and as the issue scores B's poses). History in docs/RESULTS.md, issue 23.
// Coverage: of the voxels a camera hit (its depth back-projected with the true pose) that A's or C's
// own map covers, a log-odds map of both sessions missed 32 online / 34 offline of 38 619 (session
// 20); 26 / 28 of them because the other flight's rays held them free in its own map too (e.g. the
// top edge of a shelf C passed just above). With map.keep_session_surfaces (session 29) every
// session's own occupied voxels stay: 3 online / 7 offline missed, where C's part of the merged map
// sits a few millimetres off C's own map (the seam's error, C in A's world 0.56 / 1.58 cm vs C alone
// 0.53 cm), not because a session's surface was erased. Counted with the metric's one-voxel
// tolerance: 42 834 online / 42 846 offline of the union's 42 878 (the rest is the fringe a map
// covers only through the tolerance, which the seam moves too); 42 769 / 42 773 before.
// mIoU on the voxels either run observed: online 0.8740, offline 0.8786, vs C 0.8710.
void expect_merged_map_at_least_as_good(const MapComparison& m, double miou_slack) {
  EXPECT_GE(m.union_merged, std::max(m.union_a, m.union_c) - miou_slack);
  EXPECT_GT(m.union_merged, std::min(m.union_a, m.union_c) + 0.1) << "the merged map knows both areas";
  EXPECT_GE(m.merged_on_a, m.a_on_a - miou_slack) << "merging must not spoil where A looked";
  EXPECT_GE(m.merged_on_c, m.c_on_c - miou_slack) << "nor where C looked";
  EXPECT_GE(m.covered_merged, 0.998 * m.covered_union);
  // Without keep_session_surfaces 32-34 voxels (0.08 %) were missed: this bound is 0.03 % (11 voxels).
  EXPECT_LE(m.hit_union - m.hit_merged, 0.0003 * m.hit_union) << "the merged map covers what the cameras saw";
  EXPECT_GT(m.covered_merged, std::max(m.covered_a, m.covered_c)) << "more than either run alone";
}

TEST(MergeSession, MergedSemanticMapIsAtLeastAsGoodAndCoversBothRuns) {
  ASSERT_EQ(read_bytes(flight_a_dir() + "/gt_voxels.txt"), read_bytes(flight_c_dir() + "/gt_voxels.txt"));
  std::printf("run C --map A:\n");
  const MapComparison m = compare_maps(run_c_in_a() + "/map.ot", T_run_gt(run_a(), flight_a_dir()),
                                       metrics(run_c_in_a())["map"]["miou"]);
  expect_merged_map_at_least_as_good(m, 0.0);
}

TEST(MergeSession, TwoSavedRunsMergeOffline) {
  run::MergeRunsOptions o;
  o.run_a = run_a();
  o.run_b = run_c();
  o.out_dir = (scratch_dir() / "merged").string();
  o.config = sim_preset();
  const json j = run::merge_runs(o);
  std::printf("s3m merge A C: %s\n", j["matched"].dump().c_str());
  for (const char* f : {"slam_map.bin", "kept_clouds.bin", "map.ot", "map.ply", "keyframes.txt", "merge.json",
                        "trajectory_camera_a.txt", "trajectory_camera_b.txt"})
    EXPECT_TRUE(fs::exists(fs::path(o.out_dir) / f)) << f;
  // In A's world: A's alignment scores the merged map and C's re-expressed trajectory.
  const SE3 T_a = T_run_gt(run_a(), flight_a_dir());
  const auto tree = mapping::load_semantic_map(o.out_dir + "/map.ot");
  const double own = run::score_map(*tree, flight_a_dir() + "/gt_voxels.txt", T_a).miou;
  const MapComparison m = compare_maps(o.out_dir + "/map.ot", T_a, own);
  expect_merged_map_at_least_as_good(m, 0.0);
  fs::copy_file(o.out_dir + "/trajectory_camera_b.txt", o.out_dir + "/trajectory_camera.txt");
  const double ate_c = ate_m(o.out_dir, flight_c_dir(), T_a);
  std::printf("  C's trajectory in A's world: ATE with A's alignment %.4f m\n", ate_c);
  EXPECT_LE(ate_c, 0.07);  // C's own drift before the merge point stays (measured 5.6 cm)
  // The merged session is one a later run continues in: C's start, outside A's map, is in it now.
  run::RunOptions next = merge_run_options(flight_c_dir(), (scratch_dir() / "after_merge").string());
  next.map_dir = o.out_dir;
  next.max_frames = 30;
  next.slam_only = true;
  const json states = run::run_dataset(next).metrics["tracking"]["states"];
  EXPECT_EQ(states.value("LOST", 0), 0) << states.dump();
  EXPECT_EQ(states.value("SUBMAP", 0), 0) << states.dump();
}

TEST(MergeSession, RunsThatCannotBeMergedSayWhy) {
  run::MergeRunsOptions o;
  o.config = sim_preset();
  o.out_dir = (scratch_dir() / "not_merged").string();
  auto error_of = [&](const std::string& a, const std::string& b) -> std::string {
    o.run_a = a;
    o.run_b = b;
    try {
      run::merge_runs(o);
    } catch (const Error& e) {
      return e.what();
    }
    return "";
  };
  // No overlap: C's first second only (looking where A never looked).
  const std::string c_start = cached_merge_run("run_c_start", flight_c_dir(), "", 30);
  std::string e = error_of(run_a(), c_start);
  EXPECT_NE(e.find("do not overlap"), std::string::npos) << e;
  EXPECT_NE(e.find("keyframe pairs"), std::string::npos) << e;
  // A folder without a session, a SLAM map without kept clouds, a foreign file.
  e = error_of(run_a(), (scratch_dir() / "nowhere").string());
  EXPECT_NE(e.find("is not a folder"), std::string::npos) << e;
  const fs::path slam_only = scratch_dir() / "slam_only";
  fs::create_directories(slam_only);
  fs::copy_file(run_c() + "/slam_map.bin", slam_only / "slam_map.bin", fs::copy_options::overwrite_existing);
  e = error_of(run_a(), slam_only.string());
  EXPECT_NE(e.find("no kept_clouds.bin"), std::string::npos) << e;
  const fs::path foreign = scratch_dir() / "foreign";
  fs::create_directories(foreign);
  fs::copy_file(run_c() + "/kept_clouds.bin", foreign / "slam_map.bin", fs::copy_options::overwrite_existing);
  fs::copy_file(run_c() + "/kept_clouds.bin", foreign / "kept_clouds.bin",
                fs::copy_options::overwrite_existing);
  e = error_of(run_a(), foreign.string());
  EXPECT_NE(e.find("foreign/slam_map.bin"), std::string::npos) << e;
  EXPECT_NE(e.find("SLAM map"), std::string::npos) << e;
  const fs::path copy = scratch_dir() / "copy_of_c_start";
  fs::copy(c_start, copy, fs::copy_options::recursive | fs::copy_options::overwrite_existing);
  o.out_dir = copy.string();
  e = error_of(run_a(), copy.string());
  EXPECT_NE(e.find("is one of the runs"), std::string::npos) << e;
}

}  // namespace
}  // namespace s3m::it
