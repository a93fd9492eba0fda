#pragma once
// A tiny ray-cast RGB-D renderer for SLAM tests: a textured box room (multi-scale blocky grey
// texture, so FAST finds corners at every pyramid level) seen by a pinhole camera. Exact depth,
// optional Gaussian depth noise; deterministic.
#include <cmath>
#include <cstdint>
#include <random>
#include <vector>

#include <opencv2/imgproc.hpp>

#include "s3m/core/camera.hpp"
#include "s3m/core/rgbd_frame.hpp"
#include "s3m/core/se3.hpp"

namespace s3m::test {

inline double cell_value(int a, int b, int face, int scale) {
  std::uint64_t h = 1469598103934665603ull;
  for (std::int64_t v : {std::int64_t(a), std::int64_t(b), std::int64_t(face), std::int64_t(scale)}) {
    h ^= static_cast<std::uint64_t>(v) + 0x9e3779b97f4a7c15ull;
    h *= 1099511628211ull;
    h ^= h >> 29;
  }
  return static_cast<double>(h % 1000) / 1000.0;
}

// Grey level in [0, 255] at wall coordinates (a, b) [m] on a face.
inline double room_texture(double a, double b, int face) {
  double v = 0;
  const double sizes[3] = {0.40, 0.15, 0.06};
  const double weights[3] = {0.5, 0.3, 0.2};
  for (int s = 0; s < 3; ++s)
    v += weights[s] * cell_value(static_cast<int>(std::floor(a / sizes[s])), static_cast<int>(std::floor(b / sizes[s])),
                                 face, s);
  return 30.0 + 200.0 * v;
}

struct Room {
  Vec3 lo{-3.0, -2.5, 0.0}, hi{3.0, 2.5, 3.0};  // world box [m], z up
};

inline RgbdFrame render_room(const Room& room, const PinholeCamera& cam, const SE3& T_w_c, int index, double t_s,
                             double depth_noise_m = 0.0, unsigned seed = 1) {
  RgbdFrame f;
  f.index = index;
  f.t_s = t_s;
  cv::Mat gray(cam.height, cam.width, CV_8UC1);
  f.depth_m.create(cam.height, cam.width, CV_32FC1);
  const Mat3 R = T_w_c.linear();
  const Vec3 o = T_w_c.translation();
  std::mt19937 rng(seed + 7919u * static_cast<unsigned>(index));
  std::normal_distribution<double> noise(0.0, 1.0);
  for (int v = 0; v < cam.height; ++v)
    for (int u = 0; u < cam.width; ++u) {
      const Vec3 d_c((u - cam.cx) / cam.fx, (v - cam.cy) / cam.fy, 1.0);
      const Vec3 d = R * d_c;
      double t_best = 1e9;
      int axis = 0;
      for (int k = 0; k < 3; ++k) {
        if (std::abs(d[k]) < 1e-12) continue;
        const double t = ((d[k] > 0 ? room.hi[k] : room.lo[k]) - o[k]) / d[k];
        if (t > 0 && t < t_best) t_best = t, axis = k;
      }
      const Vec3 p = o + t_best * d;
      const int face = axis * 2 + (d[axis] > 0 ? 1 : 0);
      const double a = p[(axis + 1) % 3], b = p[(axis + 2) % 3];
      gray.at<std::uint8_t>(v, u) = cv::saturate_cast<std::uint8_t>(room_texture(a, b, face));
      f.depth_m.at<float>(v, u) = static_cast<float>(t_best * (1.0 + depth_noise_m * noise(rng)));  // z = t for d_c.z = 1
    }
  cv::GaussianBlur(gray, gray, cv::Size(3, 3), 0.6);
  cv::cvtColor(gray, f.rgb, cv::COLOR_GRAY2BGR);
  return f;
}

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

}  // namespace s3m::test
