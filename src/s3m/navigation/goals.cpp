#include "s3m/navigation/goals.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

#include "s3m/core/error.hpp"

namespace s3m::navigation {
namespace {

double box_distance(const Eigen::Vector3d& p, const Eigen::Vector3d& lo, const Eigen::Vector3d& hi) {
  return (lo - p).cwiseMax(p - hi).cwiseMax(0.0).norm();
}

// A dense grid of "distance to the nearest instance voxel" around the instance, at the field's
// resolution and on the map's voxel centres, filled by stamping each voxel's neighbourhood.
struct NearGrid {
  Eigen::Vector3d origin;  // centre of cell (0, 0, 0) [m]
  Eigen::Vector3i size;
  double res;
  std::vector<float> dist;
  float& at(int x, int y, int z) { return dist[(std::size_t(z) * size.y() + y) * size.x() + x]; }
  Eigen::Vector3d centre(int x, int y, int z) const { return origin + res * Eigen::Vector3d(x, y, z); }
};

NearGrid near_grid(const DistanceField& field, const std::vector<mapping::VoxelInfo>& voxels,
                   const mapping::ObjectInstance& inst, double near_m) {
  NearGrid g;
  g.res = field.resolution();
  const auto& tree = field.tree();
  const double pad = near_m + g.res;
  const octomap::point3d lo = tree.keyToCoord(
      tree.coordToKey(inst.bbox_min_w.x() - pad, inst.bbox_min_w.y() - pad, inst.bbox_min_w.z() - pad));
  g.origin = {lo.x(), lo.y(), lo.z()};
  g.size = (((inst.bbox_max_w.array() + pad) - g.origin.array()) / g.res).ceil().cast<int>() + 1;
  g.dist.assign(std::size_t(g.size.prod()), std::numeric_limits<float>::infinity());
  for (const auto& v : voxels) {
    const Eigen::Vector3d h = Eigen::Vector3d::Constant(0.5 * v.size_m);
    const Eigen::Vector3i c0 =
        ((v.center_w - h - g.origin).array() / g.res - near_m / g.res).floor().cast<int>().max(0);
    const Eigen::Vector3i c1 = ((v.center_w + h - g.origin).array() / g.res + near_m / g.res)
                                   .ceil()
                                   .cast<int>()
                                   .min(g.size.array() - 1);
    for (int z = c0.z(); z <= c1.z(); ++z)
      for (int y = c0.y(); y <= c1.y(); ++y)
        for (int x = c0.x(); x <= c1.x(); ++x) {
          float& d = g.at(x, y, z);
          d = std::min(d, float(box_distance(g.centre(x, y, z), v.center_w - h, v.center_w + h)));
        }
  }
  return g;
}

// Free points within near_m of one instance's voxels (those of the class inside its box), nearest
// to the start first, spread out so that an unreachable pocket costs one goal, not all.
std::vector<Eigen::Vector3d> goals_near(const DistanceField& field,
                                        const std::vector<mapping::VoxelInfo>& class_voxels,
                                        const mapping::ObjectInstance& inst, const Eigen::Vector3d& start_w,
                                        const ClassGoalConfig& cfg) {
  std::vector<mapping::VoxelInfo> voxels;
  for (const auto& v : class_voxels)
    if (box_distance(v.center_w, inst.bbox_min_w, inst.bbox_max_w) <= 0.5 * v.size_m) voxels.push_back(v);
  NearGrid g = near_grid(field, voxels, inst, cfg.near_m);
  std::vector<Eigen::Vector3d> candidates, out;
  for (int z = 0; z < g.size.z(); ++z)
    for (int y = 0; y < g.size.y(); ++y)
      for (int x = 0; x < g.size.x(); ++x) {
        const Eigen::Vector3d c = g.centre(x, y, z);
        if (g.at(x, y, z) <= cfg.near_m && field.contains(c) && field.clearance(c) >= cfg.clearance_m)
          candidates.push_back(c);
      }
  std::stable_sort(candidates.begin(), candidates.end(), [&](const auto& a, const auto& b) {
    return (a - start_w).squaredNorm() < (b - start_w).squaredNorm();
  });
  for (const auto& c : candidates) {
    if (out.size() >= cfg.max_goals) break;
    const bool apart = std::all_of(out.begin(), out.end(),
                                   [&](const auto& o) { return (o - c).norm() >= cfg.goal_spacing_m; });
    if (apart) out.push_back(c);
  }
  return out;
}

}  // namespace

void ClassGoalConfig::validate() const {
  require(near_m > 0.0 && clearance_m >= 0.0 && goal_spacing_m >= 0.0 && max_goals >= 1 && max_instances >= 1,
          "class goal: near_m must be > 0, clearance_m and goal_spacing_m >= 0, max_goals and max_instances "
          ">= 1");
}

std::string classes_present(const mapping::SemanticOcTree& tree, std::size_t min_voxels) {
  std::string out;
  for (const auto& c : tree.classes().all()) {
    const auto n = mapping::object_instances(tree, c.id, min_voxels).size();
    if (n == 0) continue;
    out += (out.empty() ? "" : ", ") + c.name + " (" + std::to_string(n) +
           (n == 1 ? " instance)" : " instances)");
  }
  return out.empty() ? "none" : out;
}

ClassGoal class_goal(const DistanceField& field, ClassId label, const Eigen::Vector3d& start_w,
                     const ClassGoalConfig& cfg) {
  cfg.validate();
  const auto& tree = field.tree();
  // 1. The instances nearest to the start; 2. free points round each.
  const auto instances = mapping::object_instances(tree, label, cfg.min_voxels);
  if (instances.empty())
    throw Error("the map has no " + tree.classes().at(label).name +
                " (no instance of >= " + std::to_string(cfg.min_voxels) +
                " voxels); classes present: " + classes_present(tree, cfg.min_voxels));
  ClassGoal out;
  out.instances = instances;
  std::stable_sort(out.instances.begin(), out.instances.end(), [&](const auto& a, const auto& b) {
    return box_distance(start_w, a.bbox_min_w, a.bbox_max_w) <
           box_distance(start_w, b.bbox_min_w, b.bbox_max_w);
  });
  if (out.instances.size() > cfg.max_instances) out.instances.resize(cfg.max_instances);
  const auto class_voxels = mapping::voxels_of_class(tree, label);
  for (std::size_t k = 0; k < out.instances.size(); ++k) {
    const auto goals = goals_near(field, class_voxels, out.instances[k], start_w, cfg);
    out.goals_w.insert(out.goals_w.end(), goals.begin(), goals.end());
    out.goal_instance.insert(out.goal_instance.end(), goals.size(), k);
  }
  return out;
}

}  // namespace s3m::navigation
