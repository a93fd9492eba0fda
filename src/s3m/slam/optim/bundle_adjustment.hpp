#pragma once
// Bundle adjustment of keyframe poses and points with Ceres: a plain problem description
// (testable without a Map) plus every bundle adjustment run on a Map: the local window of local
// mapping, the full map (end of run, loop and merge corrections) and the welding BA of a merge.
#include <set>
#include <vector>

#include "s3m/core/camera.hpp"
#include "s3m/core/se3.hpp"
#include "s3m/slam/map/map.hpp"
#include "s3m/slam/odometry/keyframe_links.hpp"

namespace s3m::slam {

struct BaConfig {
  int first_iterations = 5;    // before outlier removal
  int second_iterations = 10;  // after outlier removal
  double chi2_mono = 5.991;
  double chi2_stereo = 7.815;
  int max_local_keyframes = 20;  // covisibility window optimised around the new keyframe
  // Final global BA (System::finish()): iterations before and again after outlier removal.
  int global_iterations = 15;
  // A local BA that moves a keyframe further than this from where it was is degenerate, not a
  // correction: a keyframe joined to the window by one neighbour that looks at a plain wall trades
  // rotation for translation about a point on the wall at almost no cost, while real corrections
  // stay small (see docs/DECISIONS.md, "Local BA: keyframes held where they were"). It is solved
  // again with such keyframes held where they were. Set either to a large value to turn it off.
  double max_keyframe_step_deg = 0.5;
  double max_keyframe_step_m = 0.05;
  void validate() const;
};

struct BaObservation {
  int frame = 0, point = 0;                      // indices into BaProblem's arrays
  Eigen::Vector2d uv = Eigen::Vector2d::Zero();  // measured undistorted pixel [px]
  double u_right = features::kNoRight;           // virtual right coordinate [px]; kNoRight: monocular
  double inv_sigma2 = 1;                         // 1 / level sigma^2 [1/px^2]
  // The depth row: measured inverse depth [1/m] and its weight [m^2]; inv_rho_sigma2 = 0: the
  // virtual right coordinate with inv_sigma2 (PoseObservation's rule).
  double rho = 0;
  double inv_rho_sigma2 = 0;
};

// Keypoint idx of f observed in BaProblem frame `frame` as point `point`.
BaObservation keypoint_ba_observation(const features::FrameFeatures& f, int idx, int frame, int point);

// A measured relative pose between two frames (a dense RGB-D alignment of two keyframes'
// images, keyframe_links.hpp): residual = the measurement's error in rotation [rad] and
// translation [m], each divided by its sigma.
struct BaPoseLink {
  int from = 0, to = 0;             // indices into BaProblem's frames
  SE3 T_from_to = SE3::Identity();  // maps `to` camera points into the `from` camera
  double sigma_rad = 1, sigma_m = 1;
};

struct BaProblem {
  std::vector<SE3> T_c_w;   // frame poses (world-to-camera)
  std::vector<char> fixed;  // per frame: 1 = held constant
  std::vector<Vec3> p_w;    // points [m]
  std::vector<BaObservation> obs;
  std::vector<BaPoseLink> links;
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
  int n_held_keyframes = 0;  // moved too far in the first solve (BaConfig::max_keyframe_step_*)
};

// Marks in after.fixed every keyframe free in `before` whose solved pose (after) moved further than
// config.max_keyframe_step_deg / _m from its pose in `before`; returns how many. Frames with a pose
// link are exempt: their images tie them to their neighbour, and the final global BA with links
// moves keyframes at the far end of a drifted flight by more than the limit, legitimately. The caller solves
// again from `before` with those held: such a step is a degenerate solve (a keyframe joined to the
// rest through few points), not a correction (see docs/DECISIONS.md, "Local BA: keyframes held
// where they were").
int hold_keyframes_moved_too_far(const BaProblem& before, BaProblem& after, const BaConfig& config);

// Local BA around keyframe kf: kf and its best covisible keyframes are optimised with all points
// they observe; other keyframes observing those points are held fixed. Outlier observations are
// erased from the map. A window keyframe the solve moves too far (BaConfig::max_keyframe_step_*)
// is held and the window solved again.
LocalBaStats local_bundle_adjustment(Map& map, KeyframeId kf, const PinholeCamera& camera,
                                     const BaConfig& config);

// Full bundle adjustment of every keyframe and point (the root of each sub-map fixed), written back into
// the map. Returns the number of outlier observations (left in the map, down-weighted by Huber).
// hold_large_steps: a keyframe the solve would move further than config.max_keyframe_step_deg / _m
// is held where it was and the map solved again (local BA's rule; for the end-of-run refinement,
// not for loop or merge corrections, whose seams legitimately move keyframes far).
// links: measured relative poses of keyframe pairs (keyframe_links.hpp), constraints next to the
// keypoints; a link naming a keyframe no longer in the map is skipped.
int global_bundle_adjustment(Map& map, const PinholeCamera& camera, const BaConfig& config,
                             bool hold_large_steps = false, const std::vector<KeyframeLink>& links = {});

// The welding BA (weld_ba.cpp): keyframes in window (of the moved sub-map, at the seam) and
// every point they observe are optimised, every other keyframe observing those points is held.
// Outlier observations are erased. Returns their number.
int weld_bundle_adjustment(Map& map, const std::set<KeyframeId>& window, const PinholeCamera& camera,
                           const BaConfig& config);

}  // namespace s3m::slam
