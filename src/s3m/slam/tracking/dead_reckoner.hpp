#pragma once
// Dead reckoning for the frames feature tracking loses: a second estimator beside the Tracker.
// While the map cannot place a frame, its pose comes from dense depth odometry against the last
// frame whose pose was not a guess (measured, and confirmed by a second estimate), else from the
// velocity at the moment tracking was lost (coasting, for a few frames). Why: plain walls in a
// turn leave ORB too little to track while their depth still fixes the motion (docs/DECISIONS.md,
// "Tracking: depth odometry across gaps" and "Tracking: lost frames, coasting and the bridge").
//
// Poses: T_c_w maps world points into the camera (the tracker's convention); a motion T_cur_last
// maps points of the last frame's camera into the current one's.
#include <optional>

#include "s3m/core/camera.hpp"
#include "s3m/core/rgbd_frame.hpp"
#include "s3m/core/se3.hpp"
#include "s3m/slam/odometry/depth_odometry.hpp"

namespace s3m::slam {

// YAML: the tracker's keys coast_frames and odometry_* (TrackerConfig::dead_reckoning).
struct DeadReckonerConfig {
  // Lost frames for which the last velocity keeps predicting the pose when nothing is measured.
  int coast_frames = 10;
  // Lost frames (since the last tracked one) for which depth odometry measures the motion. A
  // measured motion is accepted when a second estimate agrees with it within odometry_deg /
  // odometry_m: the velocity, or the same alignment started from no motion, or (from rest and
  // after gaps) the reverse alignment. A single plane in view makes the alignment degenerate; such
  // a view is measured along the directions it fixes and kept at the velocity along the rest
  // (DepthOdometry::align_observable). 0 = off.
  int odometry_frames = 30;
  double odometry_deg = 0.5;  // agreement of the measured motion with a second estimate [deg]
  double odometry_m = 0.015;  // ... translation [m]
  // ... or, for two alignments of one step, this fraction of the step's rotation and translation
  // where that is more, up to twice the bounds (odometry_steps_agree): estimates of a step across
  // a gap differ by a few percent of it. 0 = the bounds alone.
  double odometry_agree_fraction = 0.1;
  // A measured motion must also explain the colour images (colour_agreement, a correlation in
  // [-1, 1], at least this): in a box-like room depth odometry can align a view with the opposite
  // wall's as the same view, and both starts confirm it. Images without contrast are not judged.
  // -1 = off.
  double odometry_min_colour_agreement = 0.5;
  DepthOdometryConfig odometry;  // the depth range is the features' (set by the Tracker)
  void validate() const;         // throws s3m::Error naming the bad key
};

class DeadReckoner {
 public:
  DeadReckoner(const PinholeCamera& camera, const DeadReckonerConfig& config);

  // The motion T_cur_last that depth odometry measures between two frames and a second estimate
  // confirms, and that explains their colour images; nullopt when nothing is confirmed.
  // predicted: the velocity's motion over the same frames (its alignment is compared with it).
  std::optional<SE3> measure(const RgbdFrame& last, const RgbdFrame& cur, const SE3& predicted) const;
  // The same with no prediction (the frame after a map's first): the alignment from no motion,
  // confirmed by the reverse alignment.
  std::optional<SE3> measure_from_rest(const RgbdFrame& last, const RgbdFrame& cur) const;

  // A lost frame's pose T_c_w and whether depth odometry measured it (else the velocity's
  // prediction); nullopt when neither is available. T_c_w_last: the last frame's pose, guessed or
  // not. from_rest: the last frame was tracked with no velocity yet.
  struct Reckoning {
    SE3 T_c_w;
    bool measured = false;
  };
  std::optional<Reckoning> reckon(const RgbdFrame& frame, bool from_rest, const SE3& T_c_w_last);

  // The frame's images (shared, not copied) and its pose, which is not a guess: later lost frames
  // are measured from it.
  void keep(const RgbdFrame& frame, const SE3& T_c_w);
  // Tracking was just lost with this velocity (nullopt: none yet): coasting starts over.
  void start_coasting(const std::optional<SE3>& velocity) { velocity_ = velocity, coasted_ = 0; }
  // The lost frame ended with the reckoned pose (counts towards coast_frames), or with none, which
  // breaks the chain of dead-reckoned poses.
  void end_lost_frame(bool had_pose);
  void forget_velocity() { velocity_.reset(); }
  void forget_images() { last_ = RgbdFrame{}; }  // a pose set from outside: no odometry from before it
  // The world moved (loop correction, merge): T_new_old maps old world points to new ones.
  void move_world(const SE3& T_new_old) { T_c_w_last_ = T_c_w_last_ * T_new_old.inverse(); }
  // The per-frame velocity while lost (T_c_w(cur) = velocity * T_c_w(last)); measurements update it.
  const std::optional<SE3>& velocity() const { return velocity_; }

 private:
  std::optional<SE3> measure_motion(const RgbdFrame& last, const RgbdFrame& cur, const SE3& predicted) const;
  std::optional<SE3> confirm_by_reverse(const RgbdFrame& last, const RgbdFrame& cur,
                                        const DepthOdometry::PreparedFrame& p_last,
                                        const DepthOdometry::PreparedFrame& p_cur, const SE3& motion,
                                        double scale) const;
  bool views_may_overlap(const SE3& T_cur_last) const;
  bool colours_agree(const RgbdFrame& last, const RgbdFrame& cur, const SE3& T_cur_last) const;
  bool agree(const SE3& motion, const SE3& other) const;

  PinholeCamera camera_;
  DeadReckonerConfig config_;
  DepthOdometry odometry_;
  // The last frame with a pose that is not a guess (images shared) and that pose: a LOST frame's
  // pose is only the velocity's guess, so the next frame is measured from the frame before it.
  RgbdFrame last_;
  SE3 T_c_w_last_ = SE3::Identity();
  std::optional<SE3> velocity_;
  int coasted_ = 0;  // lost frames dead-reckoned since tracking was lost
};

}  // namespace s3m::slam
