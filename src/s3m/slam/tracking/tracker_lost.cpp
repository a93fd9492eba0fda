// What the tracker does with a frame the map could not track: dead reckoning, the bridge back into
// the map, ODOMETRY or LOST (TrackerConfig: coast_frames, bridge_*, odometry_*).
#include <algorithm>
#include <cmath>
#include <limits>

#include "s3m/slam/tracking/tracker.hpp"

namespace s3m::slam {
namespace {
// T^x on SE3, the constant-velocity motion over x frames (x = 1: T itself, bit for bit).
SE3 power(const SE3& T, double x) { return x == 1.0 ? T : se3_exp(x * se3_log(T)); }
}  // namespace

void Tracker::track_lost(Frame& cur, const RgbdFrame& frame, bool from_rest, TrackerOutput& out) {
  // 1. Dead reckoning from the last frame: depth odometry's measured motion, else the velocity.
  bool measured = false;
  const std::optional<SE3> guess = dead_reckon(frame, from_rest, measured);
  // 2. The bridge: the local map, searched from there, agrees with it.
  if (guess && bridge(cur, frame, *guess, out)) return;
  // 3. A measured view with enough depth that the map does not reach: a keyframe at the measured
  //    pose, as the first of a map, so that the next frames track against its points.
  if (measured && odometry_keyframe(cur, frame, *guess, out)) return;
  // 4. ODOMETRY at the measured pose, else LOST at the best guess (the next frame searches from it).
  state_ = measured ? FrameState::kOdometry : FrameState::kLost;
  if (velocity_) cur.T_c_w = *velocity_ * last_.T_c_w;
  if (guess) {
    cur.T_c_w = *guess;
    ++coasted_;
  } else {
    coast_velocity_.reset();  // the chain of dead-reckoned poses is broken
  }
  velocity_.reset();
  out.state = state_;
  out.T_w_c = cur.T_c_w.inverse();
  out.ref_kf = ref_kf_;
  out.T_ref_c = T_w_ref_.inverse() * out.T_w_c;
  last_.T_c_w = cur.T_c_w;
}

bool Tracker::views_may_overlap(const SE3& T_cur_last) const {
  const double fov_rad =
      2.0 * std::atan(0.5 * std::max(camera_.width / camera_.fx, camera_.height / camera_.fy));
  return rotation_angle_rad(T_cur_last.linear()) < fov_rad;
}

bool Tracker::colours_agree(const RgbdFrame& frame, const SE3& T_cur_last) const {
  // Two frames 3 s apart, the camera turned round in the dark in a box-like room: the velocity
  // predicted 36-50 deg, so the views might share something, and the alignment found the opposite
  // wall's view as the same view from both starts (180 deg off). The two walls' textures differ.
  if (config_.odometry_min_colour_agreement <= -1.0) return true;
  const std::optional<double> ncc = colour_agreement(camera_, last_frame_, frame, T_cur_last);
  return !ncc || *ncc >= config_.odometry_min_colour_agreement;
}

std::optional<SE3> Tracker::dead_reckon(const RgbdFrame& frame, bool from_rest, bool& measured) {
  measured = false;
  const bool can_measure = coasted_ < config_.odometry_frames && !last_frame_.depth_m.empty();
  // Measured from the last frame with a pose that is not a guess (LOST frames in between keep the
  // velocity's guess only), over however many frames lie between.
  const int n = std::max(1, frame.index - last_frame_.index);
  std::optional<SE3> motion;
  if (!coast_velocity_) {
    // No velocity to predict with: only a measurement from rest gives a pose.
    if (from_rest && can_measure) motion = measure_motion_from_rest(frame);
    if (!motion) return std::nullopt;
  } else if (can_measure) {
    // Not when the velocity, carried over those frames, turns the camera further than it sees: two
    // views that share nothing have no motion to measure, yet in a box-like room the alignment
    // finds the view turned round as the same view and both starts confirm it (see
    // docs/DECISIONS.md, "Tracking: depth odometry across gaps").
    const SE3 predicted = power(*coast_velocity_, n);
    if (views_may_overlap(predicted)) motion = measure_motion(frame, predicted);
  }
  if (motion && !colours_agree(frame, *motion)) motion.reset();
  if (motion) {
    measured = true;
    coast_velocity_ = power(*motion, 1.0 / n);
    return *motion * T_c_w_last_frame_;
  }
  if (coasted_ < config_.coast_frames) return *coast_velocity_ * last_.T_c_w;  // the velocity's prediction
  return std::nullopt;
}

std::optional<SE3> Tracker::measure_motion(const RgbdFrame& frame, const SE3& predicted) const {
  // 1. Dense RGB-D odometry, accepted when a second estimate agrees: the velocity (smooth motion),
  //    else the same alignment started from no motion. A well-conditioned alignment has one
  //    minimum; a degenerate one (one plane in view) slides along its valley or fails. The second
  //    start is there because a hand-held camera's motion often changes by more than the bounds in
  //    one frame, while both starts of a well-conditioned alignment agree closely (see
  //    docs/DECISIONS.md, "Tracking: depth odometry across gaps"). Two alignments
  //    agree within the bounds or a fraction of the step (odometry_agree); one started from the
  //    velocity is compared with the velocity within the bounds alone, as it may not have moved.
  //    Both frames are prepared once for every alignment (the same result as fresh images).
  const double scale = odometry_step_scale(frame);
  const DepthOdometry::PreparedFrame last = odometry_.prepare(last_frame_), cur = odometry_.prepare(frame);
  const std::optional<SE3> motion = odometry_.align(last, cur, predicted, scale);
  if (motion && poses_agree(*motion, predicted, config_.odometry_deg, config_.odometry_m)) return motion;
  const bool gap = scale > 1.0;
  std::optional<SE3> restarted;
  if (motion || gap) restarted = odometry_.align(last, cur, SE3::Identity(), scale);
  if (motion && restarted && odometry_agree(*motion, *restarted)) return motion;
  // 2. After a gap the velocity, carried over the whole gap, is a start as far off as no motion,
  //    and its alignment may fail where the other converges: the start from no motion, confirmed
  //    as from rest by the reverse alignment (see docs/DECISIONS.md, "Tracking: depth odometry
  //    across gaps").
  if (gap && restarted)
    if (const std::optional<SE3> confirmed = confirm_by_reverse(frame, last, cur, *restarted, scale))
      return confirmed;
  // 3. A degenerate view: what it constrains measured, the rest kept from the velocity. At least
  //    one plane's worth (3 directions), most of the frame overlapping the last one, and within the
  //    same bounds of the velocity, which it can only correct, not replace.
  const std::optional<ObservableMotion> m = odometry_.align_observable(last_frame_, frame, predicted);
  if (m && m->observed_directions >= 3 && m->inlier_fraction >= 0.5 &&
      poses_agree(m->T_cur_prev, predicted, config_.odometry_deg, config_.odometry_m))
    return m->T_cur_prev;
  return std::nullopt;
}

std::optional<SE3> Tracker::measure_motion_from_rest(const RgbdFrame& frame) const {
  // Started from no motion, there is no other start to compare with, so the second estimate is the
  // reverse alignment (confirm_by_reverse). Where ORB finds too few matches (a plain surface seen
  // from frames far apart), the forward alignment from rest is close to the truth on most pairs
  // (see docs/DECISIONS.md, "Tracking: depth odometry across gaps").
  const double scale = odometry_step_scale(frame);
  const DepthOdometry::PreparedFrame last = odometry_.prepare(last_frame_), cur = odometry_.prepare(frame);
  const std::optional<SE3> motion = odometry_.align(last, cur, SE3::Identity(), scale);
  if (!motion) return std::nullopt;
  return confirm_by_reverse(frame, last, cur, *motion, scale);
}

std::optional<SE3> Tracker::confirm_by_reverse(const RgbdFrame& frame,
                                               const DepthOdometry::PreparedFrame& last,
                                               const DepthOdometry::PreparedFrame& cur, const SE3& motion,
                                               double scale) const {
  // 1. This frame onto the last, also from no motion: a different problem whose minimum is the
  //    same motion only when the views fix it.
  const std::optional<SE3> reverse = odometry_.align(cur, last, SE3::Identity(), scale);
  if (!reverse) return std::nullopt;
  if (odometry_agree(motion, reverse->inverse())) return motion;
  // 2. After a gap, between two frames with no LOST frame between them, one of the two may have
  //    slid into a wrong basin (TUM fr3 cabinet 2 s apart: 5 of 19 steps, 16-89 deg off): keep the
  //    one whose step explains both depth images clearly better, if it explains them well. Across
  //    LOST frames (4 s and more) a wrong one scored 0.88 on the simulator, so not there.
  constexpr double kMinAgreement = 0.8, kMinLead = 0.15;
  if (scale <= 1.0 || frame.index - last_frame_.index != 1) return std::nullopt;
  const double forward = depth_agreement(camera_, last_frame_.depth_m, frame.depth_m, motion);
  const double backward = depth_agreement(camera_, last_frame_.depth_m, frame.depth_m, reverse->inverse());
  if (forward >= kMinAgreement && forward - backward >= kMinLead) return motion;
  if (backward >= kMinAgreement && backward - forward >= kMinLead) return reverse->inverse();
  return std::nullopt;
}

bool Tracker::odometry_agree(const SE3& motion, const SE3& other) const {
  return odometry_steps_agree(motion, other, config_.odometry_deg, config_.odometry_m,
                              config_.odometry_agree_fraction);
}

double Tracker::odometry_step_scale(const RgbdFrame& frame) const {
  // OpenCV's bounds on one alignment suit consecutive 30 Hz frames; whole periods since the last
  // frame, so that jitter in a 30 Hz stream's stamps changes nothing.
  constexpr double kNominalRateHz = 30.0;
  return std::max(1.0, std::round((frame.t_s - last_frame_.t_s) * kNominalRateHz));
}

bool Tracker::odometry_keyframe(Frame& cur, const RgbdFrame& frame, const SE3& T_c_w, TrackerOutput& out) {
  if (localize_only_ || !snapshot_ || cur.n_with_depth() < config_.min_init_depth_points) return false;
  cur = Frame::unmatched(cur.f, T_c_w);
  restart_from(cur, frame, FrameState::kOdometry, *coast_velocity_, out);  // reported as what gave the pose
  return true;
}

void Tracker::restart_from(Frame& cur, const RgbdFrame& frame, FrameState reported, const SE3& velocity,
                           TrackerOutput& out) {
  state_ = FrameState::kOk;  // the next frame tracks with the motion model again
  velocity_ = velocity;
  out.state = reported;
  out.T_w_c = cur.T_c_w.inverse();
  out.keyframe = make_request(cur, frame, /*first_of_map=*/true);
  peak_inliers_ = 0;
  out.ref_kf = ref_kf_;
  out.T_ref_c = T_w_ref_.inverse() * out.T_w_c;
  prepare_last_frame(std::move(cur), std::numeric_limits<double>::infinity());
}

bool Tracker::bridge(Frame& cur, const RgbdFrame& frame, const SE3& guess, TrackerOutput& out) {
  if (localize_only_ || !snapshot_) return false;
  if (cur.n_with_depth() < config_.min_init_depth_points) return false;
  // 1. The dead-reckoned pose and the local map's pose from it must agree (two independent estimates).
  cur = Frame::unmatched(cur.f, guess);
  auto visibility = visibility_;
  track_local_map(cur);
  const int n_inliers = cur.n_map_matched();
  if (n_inliers < config_.bridge_min_inliers ||
      !poses_agree(cur.T_c_w, guess, config_.bridge_deg, config_.bridge_m)) {
    visibility_ = std::move(visibility);
    return false;
  }
  // 2. Tracked.
  out.n_inliers = n_inliers;
  restart_from(cur, frame, FrameState::kOk, cur.T_c_w * last_.T_c_w.inverse(), out);
  return true;
}

}  // namespace s3m::slam
