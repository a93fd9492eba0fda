#pragma once
// Stamped trajectories in the two common text formats.
//  TUM:   "t tx ty tz qx qy qz qw" per line (t [s], translation [m], unit quaternion), '#' comments.
//  KITTI: 12 numbers per line, the row-major 3x4 matrix [R | t] of T_w_x; no timestamps.
#include <string>
#include <vector>

#include "s3m/core/se3.hpp"

namespace s3m::io {

using Trajectory = std::vector<StampedPose>;  // core/se3.hpp

// Throws ParseError(file, line, ...) on missing file, wrong column count, unparsable or non-finite
// numbers, a quaternion whose norm is not ~1 (|n-1| > 0.01), or timestamps that do not strictly increase.
// An empty file (only comments) is an error too: a trajectory without poses is never intended.
// A header comment naming the columns with the quaternion's w first (EuRoC: "#timestamp [ns],
// p_RS_R_x [m], ..., q_RS_w [], q_RS_x [], ...") reads "t tx ty tz qw qx qy qz" and ignores columns
// after the 8th (EuRoC's ground truth has 17). A naming header whose first column has the unit
// "[ns]" gives nanoseconds, returned as seconds; otherwise timestamps are seconds.
Trajectory read_tum_trajectory(const std::string& path);
// Atomic; time as %.6f, values as %.9g.
void write_tum_trajectory(const std::string& path, const Trajectory& trajectory);

// Timestamps are synthesised as i * dt_s. Rotations must be orthonormal within 1e-3 (then re-orthonormalised).
Trajectory read_kitti_trajectory(const std::string& path, double dt_s = 0.1);
void write_kitti_trajectory(const std::string& path, const Trajectory& trajectory);

// Reads either format: KITTI when the first data line has 12 columns, TUM otherwise.
Trajectory read_trajectory_auto(const std::string& path, double kitti_dt_s = 0.1);

std::vector<double> timestamps(const Trajectory& trajectory);

}  // namespace s3m::io
