#pragma once
// Pinhole camera with optional Brown-Conrady distortion (OpenCV's k1 k2 p1 p2 k3 order).
// Pixel coordinates: u right, v down, origin at the centre of the top-left pixel.
// Camera frame: x right, y down, z forward (metres).
#include <array>
#include <optional>
#include <string>

#include <Eigen/Core>

namespace s3m {

struct PinholeCamera {
  double fx = 525.0;  // focal length [px]
  double fy = 525.0;
  double cx = 319.5;  // principal point [px]
  double cy = 239.5;
  int width = 640;  // image size [px]
  int height = 480;
  // Depth image value / depth_factor = depth in metres (TUM: 5000, 7-Scenes/RealSense mm: 1000).
  double depth_factor = 5000.0;
  std::array<double, 5> dist{0, 0, 0, 0, 0};  // k1 k2 p1 p2 k3; all zero = no distortion
  // Stereo-like baseline used to form a virtual right coordinate u_r = u - bf / z (ORB-SLAM's bf) [px*m].
  double bf = 40.0;
  // Rolling shutter: the colour image's rows are read out one after another, the first at the
  // frame's stamp and the last this long after it [s]; 0 = a global shutter. Keypoints are moved to
  // the stamp's instant with the tracked motion (features::undo_rolling_shutter).
  double rolling_shutter_s = 0.0;

  // Throws s3m::Error naming the bad field (non-positive focal length, size, depth factor, NaN...).
  void validate() const;
  bool has_distortion() const;

  // Projects a camera-frame point (z > 0) to pixel coordinates, ignoring distortion.
  Eigen::Vector2d project(const Eigen::Vector3d& p_c) const {
    return {fx * p_c.x() / p_c.z() + cx, fy * p_c.y() / p_c.z() + cy};
  }
  // Back-projects pixel (u, v) with depth z [m] to a camera-frame point.
  Eigen::Vector3d backproject(double u, double v, double z_m) const {
    return {(u - cx) * z_m / fx, (v - cy) * z_m / fy, z_m};
  }
  bool in_image(double u, double v, double border_px = 0.0) const {
    return u >= border_px && v >= border_px && u < width - border_px && v < height - border_px;
  }
  // Intrinsics scaled to an image resized by factor s (e.g. 0.5 for half resolution).
  PinholeCamera scaled(double s) const;
};

// Well-known dataset intrinsics (from the datasets' web pages): "tum_fr1", "tum_fr2", "tum_fr3",
// "7scenes" (Microsoft 7-Scenes, depth factor 1000), "replica" (NICE-SLAM's Replica renders).
// Returns nullopt for an unknown name.
std::optional<PinholeCamera> camera_preset(const std::string& name);

}  // namespace s3m
