#pragma once
// Writing a planned path for other tools: TUM-style poses (what `s3m eval` and evo read).
#include <string>
#include <vector>

#include <Eigen/Core>

namespace s3m::navigation {

// "t x y z qx qy qz qw" per waypoint [s, m]: t is the arc length flown at speed_mps, the pose turns
// about the world z axis to look along the next segment's horizontal part (level in a z-up world;
// the last waypoint keeps the previous heading). Atomic.
void write_path_tum(const std::string& path, const std::vector<Eigen::Vector3d>& waypoints_w,
                    double speed_mps = 1.0);

}  // namespace s3m::navigation
