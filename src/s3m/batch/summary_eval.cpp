// Ground-truth evaluation of batch maps (summary.hpp): alignment, observed voxels, mIoU on a subset.
#include <cmath>
#include <filesystem>
#include <map>

#include "s3m/batch/summary.hpp"
#include "s3m/core/classes.hpp"
#include "s3m/io/gt_voxels.hpp"
#include "s3m/io/trajectory.hpp"
#include "s3m/mapping/map_io.hpp"
#include "s3m/mapping/metrics.hpp"
#include "s3m/run/evaluation.hpp"

namespace s3m::batch {
namespace fs = std::filesystem;

std::optional<SE3> T_run_gt(const std::string& run_dir, const std::string& dataset_dir) {
  const std::string est_path = run_dir + "/trajectory_camera.txt", gt_path = dataset_dir + "/groundtruth.txt";
  if (!fs::exists(est_path) || !fs::exists(gt_path)) return std::nullopt;
  const io::Trajectory est = io::read_tum_trajectory(est_path), gt = io::read_tum_trajectory(gt_path);
  std::map<double, SE3> by_time;
  for (const auto& p : gt) by_time[p.t_s] = p.T_w_x;
  std::vector<SE3> e, g;
  for (const auto& p : est) {
    const auto it = by_time.lower_bound(p.t_s - 1e-3);
    if (it != by_time.end() && std::abs(it->first - p.t_s) < 1e-3)
      e.push_back(p.T_w_x), g.push_back(it->second);
  }
  if (e.size() < 3) return std::nullopt;
  return run::align_poses(e, g);
}

std::set<std::size_t> observed_gt_voxels(const std::string& map_ot, const std::string& gt_voxels,
                                         const SE3& T_map_gt) {
  const auto tree = mapping::load_semantic_map(map_ot);
  const io::GtVoxelMap gt = io::read_gt_voxels(gt_voxels);
  const Eigen::Isometry3f T = T_map_gt.cast<float>();
  std::set<std::size_t> out;
  for (std::size_t i = 0; i < gt.centres_w.size(); ++i) {
    const Eigen::Vector3f c = T * gt.centres_w[i];
    if (tree->search(c.x(), c.y(), c.z())) out.insert(i);
  }
  return out;
}

std::size_t known_near(const std::string& map_ot, const std::string& gt_voxels, const SE3& T_map_gt,
                       const std::set<std::size_t>& subset) {
  const auto tree = mapping::load_semantic_map(map_ot);
  const io::GtVoxelMap gt = io::read_gt_voxels(gt_voxels);
  const Eigen::Isometry3f T = T_map_gt.cast<float>();
  const float r = float(tree->getResolution());
  auto known = [&](const Eigen::Vector3f& c) {
    for (int dx = -1; dx <= 1; ++dx)
      for (int dy = -1; dy <= 1; ++dy)
        for (int dz = -1; dz <= 1; ++dz)
          if (tree->search(c.x() + dx * r, c.y() + dy * r, c.z() + dz * r)) return true;
    return false;
  };
  std::size_t n = 0;
  for (std::size_t i : subset) n += known(T * gt.centres_w.at(i));
  return n;
}

double miou_on(const std::string& map_ot, const std::string& gt_voxels, const SE3& T_map_gt,
               const std::set<std::size_t>& subset) {
  const auto tree = mapping::load_semantic_map(map_ot);
  const io::GtVoxelMap gt = io::read_gt_voxels(gt_voxels);
  io::GtVoxelMap sub;
  sub.resolution_m = gt.resolution_m;
  for (std::size_t i : subset) {
    sub.centres_w.push_back(T_map_gt.cast<float>() * gt.centres_w.at(i));
    sub.labels.push_back(gt.labels.at(i));
  }
  const mapping::MapEvaluation e = mapping::evaluate_map(*tree, sub);
  std::set<ClassId> classes(sub.labels.begin(), sub.labels.end());
  classes.erase(cls::kUnknown);
  double sum = 0;
  for (ClassId c : classes) sum += e.iou.count(c) ? e.iou.at(c) : 0.0;
  return classes.empty() ? 0.0 : sum / double(classes.size());
}

}  // namespace s3m::batch
