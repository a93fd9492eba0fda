#pragma once
// Exports of a SemanticOcTree for other tools. All writes are atomic.
#include <string>
#include <vector>

#include <Eigen/Core>

#include "s3m/mapping/semantic_octree.hpp"

namespace s3m::mapping {

// octomap::ColorOcTree .ot with the same tree shape and occupancy; each node coloured by the
// palette colour of its top label (unlabelled nodes: their observed RGB). Opens in octovis.
void export_color_octree(const SemanticOcTree& tree, const std::string& path);

// Plain occupancy .bt (octomap::OcTree binary, maximum-likelihood occupancy, as octomap_server).
void export_binary_octree(const SemanticOcTree& tree, const std::string& path);

enum class PlyColor { kObserved, kClass };

// One occupied finest-resolution voxel (pruned occupied nodes are expanded into their voxels).
struct OccupiedVoxel {
  Eigen::Vector3f centre_w;  // world frame [m]
  Rgb color;                 // observed colour, or the class palette colour (see PlyColor)
  ClassId label = cls::kUnknown;
  float confidence = 0.0f;   // probability of label
};
// In the tree's leaf order (deterministic). Used by the PLY export and the ROS node's map topics.
std::vector<OccupiedVoxel> occupied_voxels(const SemanticOcTree& tree, PlyColor color = PlyColor::kObserved);

// One PLY vertex per occupied finest voxel (centre, world frame [m]) with colour, `label`
// (class id) and `confidence` (its probability). Returns the number of points written.
std::size_t export_ply(const SemanticOcTree& tree, const std::string& path, PlyColor color = PlyColor::kObserved);

}  // namespace s3m::mapping
