#pragma once
// Bundle adjustment of keyframe poses and points with Ceres: a plain problem description
// (testable without a Map) plus the local-window BA used by local mapping.
#include <vector>

#include "s3m/core/camera.hpp"
#include "s3m/core/se3.hpp"
#include "s3m/slam/map.hpp"

namespace s3m::slam {

struct BaConfig {
  int first_iterations = 5;    // before outlier removal
  int second_iterations = 10;  // after outlier removal
  double chi2_mono = 5.991;
  double chi2_stereo = 7.815;
  int max_local_keyframes = 20;  // covisibility window optimised around the new keyframe
  // Final global BA (System::finish()): iterations before and again after outlier removal.
  int global_iterations = 15;
  void validate() const;
};

struct BaObservation {
  int frame = 0, point = 0;                      // indices into BaProblem's arrays
  Eigen::Vector2d uv = Eigen::Vector2d::Zero();  // measured undistorted pixel [px]
  double u_right = -1;                           // virtual right coordinate [px]; < 0 monocular
  double inv_sigma2 = 1;                         // 1 / level sigma^2 [1/px^2]
  // The depth row: measured inverse depth [1/m] and its weight [m^2]; inv_rho_sigma2 = 0: the
  // virtual right coordinate with inv_sigma2 (PoseObservation's rule).
  double rho = 0;
  double inv_rho_sigma2 = 0;
};

// Keypoint idx of f observed in BaProblem frame `frame` as point `point`.
BaObservation keypoint_ba_observation(const features::FrameFeatures& f, int idx, int frame, int point);

struct BaProblem {
  std::vector<SE3> T_c_w;       // frame poses (world-to-camera)
  std::vector<char> fixed;      // per frame: 1 = held constant
  std::vector<Vec3> p_w;        // points [m]
  std::vector<BaObservation> obs;
};

struct BaResult {
  std::vector<char> outlier;  // per observation, after the final solve
  int n_outliers = 0;
  bool converged = false;
};

// Optimises problem in place (poses of non-fixed frames, all points): Huber-robust solve,
// removal of observations over the chi2 thresholds or behind the camera, then a second solve.
BaResult bundle_adjust(BaProblem& problem, const PinholeCamera& camera, const BaConfig& config);

struct LocalBaStats {
  int n_local_keyframes = 0, n_fixed_keyframes = 0, n_points = 0, n_observations = 0, n_outliers = 0;
};

// Local BA around keyframe kf: kf and its best covisible keyframes are optimised with all points
// they observe; other keyframes observing those points are held fixed. Outlier observations are
// erased from the map.
LocalBaStats local_bundle_adjustment(Map& map, KeyframeId kf, const PinholeCamera& camera,
                                     const BaConfig& config);

}  // namespace s3m::slam
