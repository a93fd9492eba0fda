#pragma once
// Pose-only optimisation (motion-only bundle adjustment) of one frame against known 3D points:
// robust (Huber) Gauss-Newton on the reprojection error, with ORB-SLAM's outlier rounds — after
// each round every observation is classified by its chi2 against the 95 % threshold (2 DoF for
// monocular, 3 DoF for the stereo-like RGB-D residual), outliers sit out the next round, and the
// last round runs without the robust kernel. A hand-written 6x6 solver: this runs several times
// per frame and Ceres' per-problem set-up would dominate the tracking budget.
#include <vector>

#include <Eigen/Core>

#include "s3m/core/camera.hpp"
#include "s3m/core/se3.hpp"
#include "s3m/features/frame_features.hpp"
#include "s3m/slam/optim/keypoint_measurement.hpp"

namespace s3m::slam {

struct PoseObservation {
  Vec3 p_w = Vec3::Zero();                       // point in the world [m]
  Eigen::Vector2d uv = Eigen::Vector2d::Zero();  // measured undistorted pixel [px]
  double u_right = features::kNoRight;  // measured virtual right coordinate [px]; kNoRight: monocular
  double inv_sigma2 = 1;                // 1 / sigma^2 of the keypoint's level [1/px^2]
  // The depth row (when features::has_right(u_right), keypoint_measurement.hpp): with inv_rho_sigma2 > 0 the
  // measured inverse depth rho = 1/z [1/m] with that weight [m^2]; else the virtual right
  // coordinate with inv_sigma2.
  double rho = 0;
  double inv_rho_sigma2 = 0;
};

// Keypoint i of f (its pixel, virtual right coordinate and level weight) observing point p_w.
PoseObservation keypoint_observation(const features::FrameFeatures& f, int i, const Vec3& p_w);

struct PoseOptimizerConfig {
  int rounds = 4;
  int iterations = 10;
  double chi2_mono = 5.991;    // chi2(0.95, 2 DoF)
  double chi2_stereo = 7.815;  // chi2(0.95, 3 DoF)
  void validate() const;
};

struct PoseOptimizerResult {
  SE3 T_c_w = SE3::Identity();
  std::vector<char> inlier;  // per observation
  int n_inliers = 0;
};

// Returns the refined world-to-camera pose. Uses camera fx, fy, cx, cy and (virtual right rows) bf.
PoseOptimizerResult optimize_pose(const std::vector<PoseObservation>& obs, const SE3& T_c_w_init,
                                  const PinholeCamera& camera, const PoseOptimizerConfig& config = {});

// Residual (predicted - measured) and its chi2 for one observation at pose T_c_w; returns false
// when the point is behind the camera.
bool reprojection_chi2(const PoseObservation& o, const SE3& T_c_w, const PinholeCamera& camera, double& chi2);

// The optimiser's inlier test: in front of the camera at T_c_w, chi2 within the 95 % bound of its
// degrees of freedom (config.chi2_stereo with a virtual right coordinate, else chi2_mono).
bool fits_pose(const PoseObservation& o, const SE3& T_c_w, const PinholeCamera& camera,
               const PoseOptimizerConfig& config);

}  // namespace s3m::slam
