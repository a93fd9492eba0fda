// What the tracker does with a frame the map could not track: dead reckoning, the bridge back into
// the map, ODOMETRY or LOST (TrackerConfig: coast_frames, bridge_*, odometry_*).
#include <cmath>
#include <limits>

#include "s3m/slam/tracker.hpp"

namespace s3m::slam {

void Tracker::track_lost(Frame& cur, const RgbdFrame& frame, TrackerOutput& out) {
  // 1. Dead reckoning from the last frame: depth odometry's measured motion, else the velocity.
  bool measured = false;
  const std::optional<SE3> guess = dead_reckon(frame, measured);
  // 2. The bridge: the local map, searched from there, agrees with it.
  if (guess && bridge(cur, frame, *guess, out)) return;
  // 3. A measured view with enough depth that the map does not reach: a keyframe at the measured
  //    pose, as the first of a map, so that the next frames track against its points.
  if (measured && odometry_keyframe(cur, frame, *guess, out)) return;
  // 4. ODOMETRY at the measured pose, else LOST at the best guess (the next frame searches from it).
  state_ = measured ? TrackState::kOdometry : TrackState::kLost;
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

std::optional<SE3> Tracker::dead_reckon(const RgbdFrame& frame, bool& measured) {
  measured = false;
  if (!coast_velocity_) return std::nullopt;
  if (coasted_ < config_.odometry_frames && !last_frame_.depth_m.empty()) {
    if (const std::optional<SE3> motion = measure_motion(frame)) {
      measured = true;
      coast_velocity_ = *motion;
      return *motion * last_.T_c_w;
    }
  }
  if (coasted_ < config_.coast_frames) return *coast_velocity_ * last_.T_c_w;  // the velocity's prediction
  return std::nullopt;
}

std::optional<SE3> Tracker::measure_motion(const RgbdFrame& frame) const {
  auto agrees = [&](const SE3& a, const SE3& b) { return poses_agree(a, b, config_.odometry_deg, config_.odometry_m); };
  // 1. Dense RGB-D odometry, accepted when a second estimate agrees: the velocity (smooth motion),
  //    else the same alignment started from no motion. A well-conditioned alignment has one
  //    minimum; a degenerate one (one plane in view) slides along its valley or fails. A hand-held
  //    camera's motion changes by more than the bounds in one frame in 1 of 6 frames of the
  //    kitchen, where both starts agree to 0.05 deg (docs/RESULTS.md, session 11).
  if (const std::optional<SE3> motion = odometry_.align(last_frame_, frame, *coast_velocity_)) {
    if (agrees(*motion, *coast_velocity_)) return motion;
    const std::optional<SE3> restarted = odometry_.align(last_frame_, frame, SE3::Identity());
    if (restarted && agrees(*motion, *restarted)) return motion;
  }
  // 2. A degenerate view: what it constrains measured, the rest kept from the velocity. At least
  //    one plane's worth (3 directions), most of the frame overlapping the last one, and within the
  //    same bounds of the velocity, which it can only correct, not replace.
  const std::optional<ObservableMotion> m = odometry_.align_observable(last_frame_, frame, *coast_velocity_);
  if (m && m->observed_directions >= 3 && m->inlier_fraction >= 0.5 && agrees(m->T_cur_prev, *coast_velocity_))
    return m->T_cur_prev;
  return std::nullopt;
}

bool Tracker::odometry_keyframe(Frame& cur, const RgbdFrame& frame, const SE3& T_c_w, TrackerOutput& out) {
  if (localize_only_ || !snapshot_ || cur.n_with_depth() < config_.min_init_depth_points) return false;
  cur = Frame::unmatched(cur.f, T_c_w);
  restart_from(cur, frame, TrackState::kOdometry, *coast_velocity_, out);  // reported as what gave the pose
  return true;
}

void Tracker::restart_from(Frame& cur, const RgbdFrame& frame, TrackState reported, const SE3& velocity,
                           TrackerOutput& out) {
  state_ = TrackState::kOk;  // the next frame tracks with the motion model again
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
  if (n_inliers < config_.bridge_min_inliers || !poses_agree(cur.T_c_w, guess, config_.bridge_deg, config_.bridge_m)) {
    visibility_ = std::move(visibility);
    return false;
  }
  // 2. Tracked.
  out.n_inliers = n_inliers;
  restart_from(cur, frame, TrackState::kOk, cur.T_c_w * last_.T_c_w.inverse(), out);
  return true;
}

}  // namespace s3m::slam
