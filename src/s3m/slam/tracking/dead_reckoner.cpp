// Dead reckoning of lost frames (dead_reckoner.hpp): depth odometry confirmed by a second
// estimate, else the velocity.
#include "s3m/slam/tracking/dead_reckoner.hpp"

#include <algorithm>
#include <cmath>

#include "s3m/core/error.hpp"

namespace s3m::slam {
namespace {
// How far one alignment may move, in 30 Hz frame periods between the two frames (at least 1).
// OpenCV's bounds on one alignment suit consecutive 30 Hz frames; whole periods, so that jitter in
// a 30 Hz stream's stamps changes nothing.
double step_scale(const RgbdFrame& last, const RgbdFrame& cur) {
  constexpr double kNominalRateHz = 30.0;
  return std::max(1.0, std::round((cur.t_s - last.t_s) * kNominalRateHz));
}
}  // namespace

void DeadReckonerConfig::validate() const {
  require(coast_frames >= 0, "tracker.coast_frames must be >= 0");
  require(odometry_frames >= 0 && odometry_deg >= 0 && odometry_m >= 0 && odometry_agree_fraction >= 0,
          "tracker: odometry_frames, odometry_deg, odometry_m and odometry_agree_fraction must be >= 0");
  require(odometry_min_colour_agreement >= -1 && odometry_min_colour_agreement <= 1,
          "tracker.odometry_min_colour_agreement must be in [-1, 1] (-1 = off)");
  odometry.validate();
}

DeadReckoner::DeadReckoner(const PinholeCamera& camera, const DeadReckonerConfig& config)
    : camera_(camera), config_(config), odometry_(camera, config.odometry) {
  config_.validate();
}

void DeadReckoner::keep(const RgbdFrame& frame, const SE3& T_c_w) {
  T_c_w_last_ = T_c_w;
  last_.index = frame.index;
  last_.t_s = frame.t_s;
  last_.rgb = frame.rgb;  // shared, not copied (Tracker::process()'s contract)
  last_.depth_m = frame.depth_m;
}

void DeadReckoner::end_lost_frame(bool had_pose) {
  if (had_pose)
    ++coasted_;
  else
    velocity_.reset();  // the chain of dead-reckoned poses is broken
}

std::optional<DeadReckoner::Reckoning> DeadReckoner::reckon(const RgbdFrame& frame, bool from_rest,
                                                            const SE3& T_c_w_last) {
  const bool can_measure = coasted_ < config_.odometry_frames && !last_.depth_m.empty();
  // Measured from the last frame with a pose that is not a guess (LOST frames in between keep the
  // velocity's guess only), over however many frames lie between.
  const int n = std::max(1, frame.index - last_.index);
  std::optional<SE3> motion;
  if (!velocity_) {
    // No velocity to predict with: only a measurement from rest gives a pose.
    if (from_rest && can_measure) motion = measure_from_rest(last_, frame);
    if (!motion) return std::nullopt;
  } else if (can_measure) {
    // Not when the velocity, carried over those frames, turns the camera further than it sees: two
    // views that share nothing have no motion to measure, yet in a box-like room the alignment
    // finds the view turned round as the same view and both starts confirm it (see
    // docs/DECISIONS.md, "Tracking: depth odometry across gaps").
    const SE3 predicted = se3_power(*velocity_, n);
    if (views_may_overlap(predicted)) motion = measure(last_, frame, predicted);
  }
  if (motion) {
    velocity_ = se3_power(*motion, 1.0 / n);
    return Reckoning{*motion * T_c_w_last_, true};
  }
  if (coasted_ < config_.coast_frames) return Reckoning{*velocity_ * T_c_w_last, false};  // the prediction
  return std::nullopt;
}

std::optional<SE3> DeadReckoner::measure(const RgbdFrame& last, const RgbdFrame& cur,
                                         const SE3& predicted) const {
  std::optional<SE3> motion = measure_motion(last, cur, predicted);
  if (motion && !colours_agree(last, cur, *motion)) motion.reset();
  return motion;
}

std::optional<SE3> DeadReckoner::measure_from_rest(const RgbdFrame& last, const RgbdFrame& cur) const {
  // Started from no motion, there is no other start to compare with, so the second estimate is the
  // reverse alignment (confirm_by_reverse). Where ORB finds too few matches (a plain surface seen
  // from frames far apart), the forward alignment from rest is close to the truth on most pairs
  // (see docs/DECISIONS.md, "Tracking: depth odometry across gaps").
  const double scale = step_scale(last, cur);
  const DepthOdometry::PreparedFrame p_last = odometry_.prepare(last), p_cur = odometry_.prepare(cur);
  const std::optional<SE3> motion = odometry_.align(p_last, p_cur, SE3::Identity(), scale);
  if (!motion) return std::nullopt;
  std::optional<SE3> confirmed = confirm_by_reverse(last, cur, p_last, p_cur, *motion, scale);
  if (confirmed && !colours_agree(last, cur, *confirmed)) confirmed.reset();
  return confirmed;
}

std::optional<SE3> DeadReckoner::measure_motion(const RgbdFrame& last, const RgbdFrame& cur,
                                                const SE3& predicted) const {
  // 1. Dense RGB-D odometry, accepted when a second estimate agrees: the velocity (smooth motion),
  //    else the same alignment started from no motion. A well-conditioned alignment has one
  //    minimum; a degenerate one (one plane in view) slides along its valley or fails. The second
  //    start is there because a hand-held camera's motion often changes by more than the bounds in
  //    one frame, while both starts of a well-conditioned alignment agree closely. Two alignments
  //    agree within the bounds or a fraction of the step (agree()); one started from the velocity
  //    is compared with the velocity within the bounds alone, as it may not have moved. Both
  //    frames are prepared once for every alignment (the same result as fresh images).
  const double scale = step_scale(last, cur);
  const DepthOdometry::PreparedFrame p_last = odometry_.prepare(last), p_cur = odometry_.prepare(cur);
  const std::optional<SE3> motion = odometry_.align(p_last, p_cur, predicted, scale);
  if (motion && poses_agree(*motion, predicted, config_.odometry_deg, config_.odometry_m)) return motion;
  const bool gap = scale > 1.0;
  std::optional<SE3> restarted;
  if (motion || gap) restarted = odometry_.align(p_last, p_cur, SE3::Identity(), scale);
  if (motion && restarted && agree(*motion, *restarted)) return motion;
  // 2. After a gap the velocity, carried over the whole gap, is a start as far off as no motion,
  //    and its alignment may fail where the other converges: the start from no motion, confirmed
  //    as from rest by the reverse alignment.
  if (gap && restarted)
    if (const std::optional<SE3> confirmed = confirm_by_reverse(last, cur, p_last, p_cur, *restarted, scale))
      return confirmed;
  // 3. A degenerate view: what it constrains measured, the rest kept from the velocity. At least
  //    one plane's worth (3 directions), most of the frame overlapping the last one, and within the
  //    same bounds of the velocity, which it can only correct, not replace.
  const std::optional<ObservableMotion> m = odometry_.align_observable(last, cur, predicted);
  if (m && m->observed_directions >= 3 && m->inlier_fraction >= 0.5 &&
      poses_agree(m->T_cur_prev, predicted, config_.odometry_deg, config_.odometry_m))
    return m->T_cur_prev;
  return std::nullopt;
}

std::optional<SE3> DeadReckoner::confirm_by_reverse(const RgbdFrame& last, const RgbdFrame& cur,
                                                    const DepthOdometry::PreparedFrame& p_last,
                                                    const DepthOdometry::PreparedFrame& p_cur,
                                                    const SE3& motion, double scale) const {
  // 1. This frame onto the last, also from no motion: a different problem whose minimum is the
  //    same motion only when the views fix it.
  const std::optional<SE3> reverse = odometry_.align(p_cur, p_last, SE3::Identity(), scale);
  if (!reverse) return std::nullopt;
  if (agree(motion, reverse->inverse())) return motion;
  // 2. After a gap, between two frames with no LOST frame between them, one of the two may have
  //    slid into a wrong basin (TUM fr3 cabinet 2 s apart: 5 of 19 steps, 16-89 deg off): keep the
  //    one whose step explains both depth images clearly better, if it explains them well. Across
  //    LOST frames (4 s and more) a wrong one scored 0.88 on the simulator, so not there.
  constexpr double kMinAgreement = 0.8, kMinLead = 0.15;
  if (scale <= 1.0 || cur.index - last.index != 1) return std::nullopt;
  const double forward = depth_agreement(camera_, last.depth_m, cur.depth_m, motion);
  const double backward = depth_agreement(camera_, last.depth_m, cur.depth_m, reverse->inverse());
  if (forward >= kMinAgreement && forward - backward >= kMinLead) return motion;
  if (backward >= kMinAgreement && backward - forward >= kMinLead) return reverse->inverse();
  return std::nullopt;
}

bool DeadReckoner::views_may_overlap(const SE3& T_cur_last) const {
  const double fov_rad =
      2.0 * std::atan(0.5 * std::max(camera_.width / camera_.fx, camera_.height / camera_.fy));
  return rotation_angle_rad(T_cur_last.linear()) < fov_rad;
}

bool DeadReckoner::colours_agree(const RgbdFrame& last, const RgbdFrame& cur, const SE3& T_cur_last) const {
  // Two frames 3 s apart, the camera turned round in the dark in a box-like room: the velocity
  // predicted 36-50 deg, so the views might share something, and the alignment found the opposite
  // wall's view as the same view from both starts (180 deg off). The two walls' textures differ.
  if (config_.odometry_min_colour_agreement <= -1.0) return true;
  const std::optional<double> ncc = colour_agreement(camera_, last, cur, T_cur_last);
  return !ncc || *ncc >= config_.odometry_min_colour_agreement;
}

bool DeadReckoner::agree(const SE3& motion, const SE3& other) const {
  return odometry_steps_agree(motion, other, config_.odometry_deg, config_.odometry_m,
                              config_.odometry_agree_fraction);
}

}  // namespace s3m::slam
