#pragma once
// Ground-truth semantic voxel map (produced by the simulator, consumed by map evaluation).
// Text format:
//   # s3m ground-truth voxel map v1
//   resolution <m>
//   x y z class_id          (voxel centre in world metres, one voxel per line)
#include <string>
#include <vector>

#include <Eigen/Core>

#include "s3m/core/classes.hpp"

namespace s3m::io {

struct GtVoxelMap {
  double resolution_m = 0.05;
  std::vector<Eigen::Vector3f> centres_w;  // world frame [m]
  std::vector<ClassId> labels;             // same length as centres_w
};

void write_gt_voxels(const std::string& path, const GtVoxelMap& map);  // atomic; throws on size mismatch
GtVoxelMap read_gt_voxels(const std::string& path);                    // ParseError with file:line

}  // namespace s3m::io
