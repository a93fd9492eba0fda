#pragma once
// Camera pose from 2D-3D matches for relocalisation: PnP RANSAC (OpenCV) on matched map points,
// then Levenberg-Marquardt refinement on the inliers.
#include <cstdint>
#include <vector>

#include <Eigen/Core>

#include "s3m/core/camera.hpp"
#include "s3m/core/se3.hpp"

namespace s3m::slam {

struct PnpConfig {
  int iterations = 300;
  double reprojection_px = 4.0;  // inlier threshold [px]
  double confidence = 0.99;
  int min_inliers = 30;  // ORB-SLAM relocalises with >= 50 after refinement; 30 after RANSAC
  void validate() const;
};

// The camera to pass with keypoint pixels: features are undistorted at extraction, so the same
// intrinsics without distortion (relocalisation and the tracker's wide-gap step).
inline PinholeCamera without_distortion(PinholeCamera c) {
  c.dist = {0, 0, 0, 0, 0};
  return c;
}

struct PnpResult {
  bool success = false;
  SE3 T_w_c = SE3::Identity();  // camera-to-world
  std::vector<int> inliers;     // indices into the input matches
  double rmse_px = 0.0;         // reprojection RMSE over inliers
};

// points_w: 3D points in the world frame [m]; pixels: their observations (distorted pixel
// coordinates when the camera has distortion). Never throws for a failed estimate: success=false.
PnpResult solve_pnp_ransac(const std::vector<Vec3>& points_w, const std::vector<Eigen::Vector2d>& pixels,
                           const PinholeCamera& camera, const PnpConfig& config = {});

}  // namespace s3m::slam
