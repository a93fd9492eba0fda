#pragma once
// Which goal points a robot can reach at all, and how far away they are through free space: a
// Dijkstra search over the distance field's voxels (26-connected) that have the clearance. The
// planner uses it to skip goals in pockets it could never enter (rather than spending its time
// limit on each) and to try the nearest goal by path, not by straight line. World frame, metres.
#include <vector>

#include <Eigen/Core>

#include "s3m/navigation/distance_field.hpp"

namespace s3m::navigation {

struct Reachability {
  std::vector<double> lengths_m;  // per point: grid path length from the start, infinity if unreachable
  std::vector<std::vector<Eigen::Vector3d>> paths_w;  // per point: voxel centres from the start's to its own
  std::size_t voxels_reached = 0;  // voxels connected to the start (all of them when a point is unreachable)
};

// Grid path lengths from start_w to each of points_w through the field's voxels with clearance >=
// required_m (a point counts as its voxel). Stops once every point is settled.
Reachability grid_reachability(const DistanceField& field, const Eigen::Vector3d& start_w,
                               const std::vector<Eigen::Vector3d>& points_w, double required_m);

}  // namespace s3m::navigation
