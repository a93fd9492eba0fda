// What the tracker does with a frame the map could not track: dead reckoning (DeadReckoner), the
// bridge back into the map, ODOMETRY or LOST (TrackerConfig: bridge_*, dead_reckoning).
#include <algorithm>
#include <cmath>
#include <limits>

#include "s3m/slam/tracking/tracker.hpp"

namespace s3m::slam {

void Tracker::track_lost(Frame& cur, const RgbdFrame& frame, bool from_rest, TrackerOutput& out) {
  // 1. Dead reckoning from the last frame: depth odometry's measured motion, else the velocity.
  const std::optional<DeadReckoner::Reckoning> reckoned = reckoner_.reckon(frame, from_rest, last_.T_c_w);
  const bool measured = reckoned && reckoned->measured;
  const std::optional<SE3> guess = reckoned ? std::optional<SE3>(reckoned->T_c_w) : std::nullopt;
  // 2. The bridge: the local map, searched from there, agrees with it.
  if (guess && bridge(cur, frame, *guess, out)) return;
  // 3. A measured view with enough depth that the map does not reach: a keyframe at the measured
  //    pose, as the first of a map, so that the next frames track against its points.
  if (measured && odometry_keyframe(cur, frame, *guess, out)) return;
  // 4. ODOMETRY at the measured pose, else LOST at the best guess (the next frame searches from it).
  state_ = measured ? FrameState::kOdometry : FrameState::kLost;
  if (velocity_) cur.T_c_w = *velocity_ * last_.T_c_w;
  if (guess) cur.T_c_w = *guess;
  reckoner_.end_lost_frame(guess.has_value());
  velocity_.reset();
  out.state = state_;
  out.T_w_c = cur.T_c_w.inverse();
  out.ref_kf = ref_kf_;
  out.T_ref_c = T_w_ref_.inverse() * out.T_w_c;
  last_.T_c_w = cur.T_c_w;
}

bool Tracker::odometry_keyframe(Frame& cur, const RgbdFrame& frame, const SE3& T_c_w, TrackerOutput& out) {
  if (localize_only_ || !snapshot_ || cur.n_with_depth() < config_.min_init_depth_points) return false;
  cur = Frame::unmatched(cur.f, T_c_w);
  restart_from(cur, frame, FrameState::kOdometry, *reckoner_.velocity(),
               out);  // reported as what gave the pose
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
