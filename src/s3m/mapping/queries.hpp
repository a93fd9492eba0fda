#pragma once
// Read-only questions a user asks of a semantic map. Only occupied voxels (occupancy above the
// tree's threshold) with at least one label count; a voxel's class is its top label.
#include <optional>
#include <vector>

#include <Eigen/Core>

#include "s3m/mapping/semantic_octree.hpp"

namespace s3m::mapping {

struct VoxelInfo {
  Eigen::Vector3d center_w = Eigen::Vector3d::Zero();  // world frame [m]
  double size_m = 0.0;                                 // edge length (larger for pruned nodes)
  ClassId label = cls::kUnknown;
  float confidence = 0.0f;  // probability of label
  double occupancy = 0.0;   // probability
};

// The occupied, labelled voxel containing p_w; nullopt if unknown, free or unlabelled there.
std::optional<VoxelInfo> class_at(const SemanticOcTree& tree, const Eigen::Vector3d& p_w);

// Occupied leaves whose top label is `label`, in the tree's depth-first order.
std::vector<VoxelInfo> voxels_of_class(const SemanticOcTree& tree, ClassId label);

// Finest-resolution voxel count per top label: counts[id] for every ClassId up to the largest present.
std::vector<std::size_t> class_voxel_counts(const SemanticOcTree& tree);

struct ObjectInstance {
  ClassId label = cls::kUnknown;
  std::size_t voxels = 0;                               // finest-resolution voxels
  Eigen::Vector3d centroid_w = Eigen::Vector3d::Zero();  // mean voxel centre [m]
  Eigen::Vector3d bbox_min_w = Eigen::Vector3d::Zero(), bbox_max_w = Eigen::Vector3d::Zero();  // [m]
  double volume_m3 = 0.0;                               // voxels * resolution^3
  double mean_confidence = 0.0;
};

// Connected components (26-connectivity) of occupied finest voxels sharing top label `label`,
// with at least min_voxels voxels; largest first (ties: lower centroid x, y, z). Deterministic.
std::vector<ObjectInstance> object_instances(const SemanticOcTree& tree, ClassId label, std::size_t min_voxels = 1);

}  // namespace s3m::mapping
