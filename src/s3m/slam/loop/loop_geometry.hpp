#pragma once
// Geometric verification of a loop candidate with RGB-D: matched features have 3D points in both
// keyframes' camera frames, so the relative pose is an SE3 found by 3-point RANSAC + Umeyama
// (closed-form least squares, Horn/Umeyama without scale), then refined on all inliers.
#include <cstdint>
#include <vector>

#include "s3m/core/se3.hpp"

namespace s3m::slam {

struct Se3RansacConfig {
  int max_iterations = 300;
  // A pair (p_a, p_b) is an inlier when |p_a - T_a_b p_b| < threshold_m + depth_ratio * z_b:
  // depth noise of structured-light / ToF sensors grows with range.
  double threshold_m = 0.03;
  double depth_ratio = 0.02;
  int min_inliers = 20;
  uint64_t seed = 1;
  void validate() const;
};

struct Se3RansacResult {
  bool success = false;  // enough inliers
  SE3 T_a_b = SE3::Identity();
  std::vector<int> inliers;  // indices into the input pairs
  double rmse_m = 0.0;       // over inliers after refinement
};

// Estimates T_a_b with p_a ≈ T_a_b * p_b from putative correspondences (same length vectors).
Se3RansacResult estimate_se3_ransac(const std::vector<Vec3>& p_a, const std::vector<Vec3>& p_b,
                                    const Se3RansacConfig& config = {});

// Closed-form least-squares rigid transform (Umeyama, no scale) over the selected pairs.
SE3 fit_se3(const std::vector<Vec3>& p_a, const std::vector<Vec3>& p_b, const std::vector<int>& indices);

}  // namespace s3m::slam
