#pragma once
// What people leave in a map: occupied voxels near where a person walked that the static
// ground-truth map does not explain (simulator sequences with people, sim/people.hpp).
#include <string>
#include <vector>

#include <Eigen/Core>

#include "s3m/core/se3.hpp"
#include "s3m/io/gt_voxels.hpp"
#include "s3m/mapping/semantic_octree.hpp"

namespace s3m::run {

struct GhostCount {
  std::size_t occupied = 0;    // occupied finest-level voxels of the map
  std::size_t near_paths = 0;  // ... near a person's path
  std::size_t ghosts = 0;      // ... of those, not explained by the static ground truth
};

// A voxel is near a path when its centre, moved by T_gt_map into the ground truth's world, lies
// within near_m horizontally of a position a person stood at (people_xy) and below top_m; it is
// explained when a ground-truth voxel lies in its 3x3x3 neighbourhood (one voxel of noise or
// alignment).
GhostCount count_ghost_voxels(const mapping::SemanticOcTree& map, const SE3& T_gt_map,
                              const io::GtVoxelMap& gt, const std::vector<Eigen::Vector2d>& people_xy,
                              double near_m = 0.32, double top_m = 2.0);

// people.txt of a simulated sequence (`frame t_s person x_m y_m` lines): every position.
std::vector<Eigen::Vector2d> read_people_positions(const std::string& path);

}  // namespace s3m::run
