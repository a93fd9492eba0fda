#pragma once
// A ROS 2 CameraInfo as s3m's camera.
#include "s3m/core/camera.hpp"
#include "s3m/rosbag2/cdr.hpp"

namespace s3m::rosbag2 {

// plumb_bob (k1 k2 p1 p2 k3) is s3m's model as it is. rational_polynomial (k1 k2 p1 p2 k3 k4 k5
// k6, the Azure Kinect's) is s3m's model when k4..k6 are 0, and otherwise the Brown-Conrady
// coefficients that distort the image's pixels the same way in the least-squares sense. Throws
// s3m::Error naming `where` for another model with non-zero coefficients or invalid intrinsics.
// bf: the camera's P[3] when it says a baseline, else default_bf.
PinholeCamera camera_from_info(const CameraInfo& info, double default_bf, const std::string& where);

// Whether the recording's camera is the one a camera file describes (size and fx within 1 %).
bool info_matches(const CameraInfo& info, const PinholeCamera& camera);

}  // namespace s3m::rosbag2
