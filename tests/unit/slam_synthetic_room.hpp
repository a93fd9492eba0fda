#pragma once
// A tiny ray-cast RGB-D renderer for SLAM tests: a textured box room (multi-scale blocky grey
// texture, so FAST finds corners at every pyramid level) seen by a pinhole camera. Exact depth,
// optional Gaussian depth noise; deterministic.
#include <cmath>

#include "s3m/core/camera.hpp"
#include "s3m/core/rgbd_frame.hpp"
#include "s3m/core/se3.hpp"

namespace s3m::test {

struct Room {
  Vec3 lo{-3.0, -2.5, 0.0}, hi{3.0, 2.5, 3.0};  // world box [m], z up
};

// The room seen from T_w_c: grey texture (as BGR) and exact depth [m] along the optical axis,
// times (1 + depth_noise_m * N(0, 1)) per pixel when depth_noise_m > 0 (seeded by seed and index).
// Defined in slam_synthetic_room.cpp, which the sanitizer build compiles optimised and
// uninstrumented (tests/CMakeLists.txt).
RgbdFrame render_room(const Room& room, const PinholeCamera& cam, const SE3& T_w_c, int index, double t_s,
                      double depth_noise_m = 0.0, unsigned seed = 1);

// The room tests' camera: Kinect-like 640x480 intrinsics, bf 40 px*m.
inline PinholeCamera room_camera() {
  PinholeCamera c;
  c.fx = c.fy = 525;
  c.cx = 319.5;
  c.cy = 239.5;
  c.bf = 40;
  return c;
}

// A UAV-like flight: an ellipse at ~1.5 m height with gentle bobbing, yaw turning with the path.
inline SE3 uav_pose(int i, int n) {
  const double s = 2.0 * M_PI * i / n;
  const Vec3 pos(1.0 * std::cos(s), 0.7 * std::sin(s), 1.5 + 0.1 * std::sin(3 * s));
  const double yaw = s + 0.6, pitch = 0.1 * std::sin(2 * s);
  const Vec3 fwd(std::cos(yaw) * std::cos(pitch), std::sin(yaw) * std::cos(pitch), -std::sin(pitch));
  const Vec3 right = fwd.cross(Vec3::UnitZ()).normalized();
  const Vec3 down = fwd.cross(right);
  Mat3 R;
  R.col(0) = right;
  R.col(1) = down;
  R.col(2) = fwd;
  return make_se3(R, pos);
}

// A level camera at the room's centre, 1.5 m up, turned by yaw_deg about the vertical from
// uav_pose(0, n)'s heading. The room is symmetric about its centre: the view turned 180 deg sees the
// opposite walls at the same distances (same depth, other texture).
inline SE3 centre_pose(double yaw_deg) {
  return make_se3(so3_exp(Vec3(0.0, 0.0, yaw_deg * M_PI / 180)) * uav_pose(0, 300).linear(), Vec3(0.0, 0.0, 1.5));
}

}  // namespace s3m::test
