#include "s3m/slam/tracking/tracker.hpp"

#include <algorithm>
#include <iterator>
#include <limits>

#include "s3m/core/error.hpp"
#include "s3m/slam/map/depth_points.hpp"

namespace s3m::slam {
namespace {
// Points from depth a frame hands on besides the close ones: ORB-SLAM's 100 VO points for the
// next frame. A pending keyframe's are the mapper's min_new_points (pending_new_points_).
constexpr int kMinVoPoints = 100;

DeadReckonerConfig reckoner_config(const TrackerConfig& tracker, const features::FeatureConfig& features) {
  DeadReckonerConfig c = tracker.dead_reckoning;
  c.odometry.min_depth_m = features.min_depth_m;  // the depth the features trust
  c.odometry.max_depth_m = features.max_depth_m;
  return c;
}
}  // namespace

int Tracker::Frame::n_matched() const {
  return static_cast<int>(std::count(matched.begin(), matched.end(), 1));
}

int Tracker::Frame::n_map_matched() const {
  int k = 0;
  for (std::size_t i = 0; i < matched.size(); ++i) k += (matched[i] && pid[i] != kNoId);
  return k;
}

int Tracker::Frame::n_with_depth() const {
  return static_cast<int>(std::count_if(f->depth_m.begin(), f->depth_m.end(), [](float z) { return z > 0; }));
}

Tracker::Frame Tracker::Frame::unmatched(std::shared_ptr<const features::FrameFeatures> f, const SE3& T_c_w) {
  const int n = f->size();
  return Frame{std::move(f), T_c_w, std::vector<PointId>(n, kNoId), std::vector<Vec3>(n, Vec3::Zero()),
               std::vector<char>(n, 0)};
}

Tracker::Tracker(const PinholeCamera& camera, const features::FeatureConfig& features,
                 const TrackerConfig& config, int pending_new_points)
    : camera_(camera),
      feature_config_(features),
      config_(config),
      pending_new_points_(pending_new_points),
      extractor_(features.orb),
      reckoner_(camera, reckoner_config(config, features)) {
  camera_.validate();
  require(pending_new_points_ >= 0, "tracker: pending_new_points must be >= 0");
  feature_config_.validate();
  config_.validate();
}

void Tracker::set_snapshot(std::shared_ptr<const LocalMapSnapshot> snapshot) {
  if (snapshot && !follow_merges(*snapshot)) return;  // a sub-map left behind
  // Keyframe poses may have moved (local BA, loop closure): move the last frame and its points
  // rigidly with the keyframe they are stored against, so the motion model stays consistent.
  if (snapshot && ref_kf_ != kNoId)
    for (const auto& k : snapshot->keyframes)
      if (k.id == ref_kf_) {
        const SE3 correction = k.T_w_c * T_w_ref_.inverse();
        last_.T_c_w = last_.T_c_w * correction.inverse();
        reckoner_.move_world(correction);
        for (std::size_t i = 0; i < last_.p_w.size(); ++i)
          if (last_.matched[i]) last_.p_w[i] = correction * last_.p_w[i];
        T_w_ref_ = k.T_w_c;
        break;
      }
  // A snapshot answers every request up to its reference keyframe: their points are in it now.
  if (snapshot)
    pending_.erase(std::remove_if(pending_.begin(), pending_.end(),
                                  [&](const PendingKeyFrame& p) { return p.id <= snapshot->reference_kf; }),
                   pending_.end());
  snapshot_ = std::move(snapshot);
}

void Tracker::set_pose(const SE3& T_w_c) {
  last_.T_c_w = T_w_c.inverse();
  std::fill(last_.matched.begin(), last_.matched.end(), 0);
  velocity_.reset();
  recent_.clear();
  reckoner_.forget_velocity();
  reckoner_.forget_images();   // no odometry from images of before the new pose
  state_ = FrameState::kLost;  // the next frame tracks against the local map from this pose
  resume_from_pose_ = true;
}

void Tracker::continue_map(KeyframeId next_keyframe_id) {
  require(state_ == FrameState::kNotInitialized && n_requests_ == 0,
          "Tracker::continue_map: only before the first frame");
  n_requests_ = next_keyframe_id;
  state_ = FrameState::kLost;
}

// Moves everything tracking holds in world coordinates by T_new_old when this sub-map was merged
// into the snapshot's (the mapping stage moved the map rigidly by the same transform).
bool Tracker::follow_merges(const LocalMapSnapshot& snapshot) {
  SE3 T = SE3::Identity();
  int s = submap_;
  while (s != snapshot.submap) {
    const auto it = snapshot.merged_into.find(s);
    if (it == snapshot.merged_into.end()) return false;
    T = it->second.second * T;
    s = it->second.first;
  }
  if (s == submap_) return true;
  last_.T_c_w = last_.T_c_w * T.inverse();
  for (auto& [t, T_c_w] : recent_) T_c_w = T_c_w * T.inverse();
  reckoner_.move_world(T);
  for (std::size_t i = 0; i < last_.p_w.size(); ++i)
    if (last_.matched[i]) last_.p_w[i] = T * last_.p_w[i];
  T_w_ref_ = T * T_w_ref_;
  for (PendingKeyFrame& p : pending_)
    for (Vec3& x : p.p_w) x = T * x;
  submap_ = s;
  return true;
}

void Tracker::start_new_map(int submap) {
  require(!localize_only_, "Tracker::start_new_map: not in localisation only");
  state_ = FrameState::kNotInitialized;
  submap_ = submap;
  snapshot_.reset();
  pending_.clear();
  visibility_.clear();
  velocity_.reset();
  recent_.clear();
  reckoner_.forget_velocity();
  resume_from_pose_ = false;
  ref_kf_ = kNoId;
  T_w_ref_ = SE3::Identity();
}

void Tracker::set_local_map(std::shared_ptr<const LocalMapSnapshot> snapshot, int frame_index) {
  require(snapshot && !snapshot->keyframes.empty(), "Tracker::set_local_map: empty local map");
  ref_kf_ = snapshot->reference_kf;
  T_w_ref_ = snapshot->keyframes.front().T_w_c;
  submap_ = snapshot->submap;  // the caller's pose (set_pose) is in its frame
  last_keyframe_frame_ = frame_index;
  if (localize_only_) visibility_.clear();  // statistics only travel with keyframe requests
  snapshot_ = std::move(snapshot);
}

TrackerOutput Tracker::process(const RgbdFrame& frame, int pending_keyframes) {
  // 1. Features; the rest is retrack()'s (a frame tracked again later skips this step).
  return retrack(frame, extract(frame), pending_keyframes);
}

std::shared_ptr<const features::FrameFeatures> Tracker::extract(const RgbdFrame& frame) const {
  return std::make_shared<features::FrameFeatures>(
      features::compute_frame_features(frame.rgb, frame.depth_m, camera_, extractor_, feature_config_,
                                       depth_instant(frame), frame.dynamic_mask, shutter_motion()));
}

std::optional<SE3> Tracker::depth_instant(const RgbdFrame& frame) const {
  if (!velocity_ || state_ != FrameState::kOk) return std::nullopt;
  return depth_instant(frame, *velocity_);
}

std::optional<SE3> Tracker::depth_instant(const RgbdFrame& frame, const SE3& step) const {
  if (!config_.depth_time_compensation || frame.depth_dt_s == 0.0) return std::nullopt;
  // The motion spans one step of step_dt_s_; a gap longer than a step (or a clock that went
  // backwards) is not something to extrapolate it over.
  const double s = frame.depth_dt_s / step_dt_s_;
  if (!(step_dt_s_ > 0) || !(std::abs(s) <= 1.0)) return std::nullopt;
  return se3_power(step, s);  // T_d_c: the camera moved on by s steps
}

features::RollingShutter Tracker::shutter_motion() const {
  const double readout = camera_.rolling_shutter_s;
  // Measured over the frames tracked in a row up to the previous one: at least two steps, more
  // while within kShutterMotionS. One step's motion is as noisy as two poses, and the correction
  // feeds that noise into the next pose and so into the next step: on the simulator's rolling-
  // shutter flights one step made the error grow to 7-16 cm where two to three steps gave 1.2-2.5.
  constexpr double kShutterMotionS = 0.07;
  if (readout <= 0 || state_ != FrameState::kOk || recent_.empty() || recent_.back().first != last_frame_t_s_)
    return {};
  const auto& [t_end, T_end] = recent_.back();
  const std::pair<double, SE3>* base = nullptr;
  int steps = 0;  // from base to the newest pose
  for (auto it = std::next(recent_.rbegin()); it != recent_.rend(); ++it) {
    if (steps >= 2 && t_end - it->first > kShutterMotionS) break;
    base = &*it;
    ++steps;
  }
  if (steps < 2 || !(t_end > base->first)) return {};
  return {readout, SE3(T_end * base->second.inverse()), t_end - base->first};
}

void Tracker::reread_depth(Frame& cur, const RgbdFrame& frame) const {
  const std::optional<SE3> T_d_c = depth_instant(frame, cur.T_c_w * last_.T_c_w.inverse());
  if (!T_d_c || frame.depth_m.empty()) return;
  auto f = std::make_shared<features::FrameFeatures>(*cur.f);
  features::read_keypoint_depths(*f, features::raw_pixels(*f, camera_), frame.depth_m, camera_,
                                 feature_config_, T_d_c);
  cur.f = std::move(f);
}

TrackerOutput Tracker::retrack(const RgbdFrame& frame,
                               std::shared_ptr<const features::FrameFeatures> features,
                               int pending_keyframes) {
  if (frame.t_s != last_frame_t_s_) {  // a deferred frame is retracked: same step
    prev_frame_t_s_ = last_frame_t_s_;
    step_dt_s_ = frame.t_s - last_frame_t_s_;
    last_frame_t_s_ = frame.t_s;
  }
  TrackerOutput out = track(frame, std::move(features), pending_keyframes);
  if (!out.deferred && out.state != FrameState::kLost) reckoner_.keep(frame, last_.T_c_w);
  return out;
}

TrackerOutput Tracker::track(const RgbdFrame& frame, std::shared_ptr<const features::FrameFeatures> features,
                             int pending) {
  TrackerOutput out;
  out.features = features;
  Frame cur = Frame::unmatched(std::move(features), SE3::Identity());
  const int n = cur.f->size();
  // 2. The first frame with enough depth starts the map.
  if (state_ == FrameState::kNotInitialized) {
    initialize(cur, frame, out);
    return out;
  }
  // 3. Frame to frame: motion model, else the reference keyframe.
  bool ok = false;
  // Right after the first keyframe there is no velocity yet: predict no motion (a guided search
  // around the last pose; a UAV starts at rest) before falling back to the reference keyframe.
  if (state_ == FrameState::kOk) ok = track_motion_model(cur, velocity_.value_or(SE3::Identity()));
  if (!ok) {
    cur = Frame::unmatched(cur.f, last_.T_c_w);
    // After relocalisation the pose prior is good while the reference keyframe's view may be too
    // different for brute-force matching: local-map tracking by projection decides directly.
    ok = resume_from_pose_ || track_reference_keyframe(cur);
  }
  resume_from_pose_ = false;
  // 4. Local map: more matches, final pose; unsynchronised depth first read again with the motion
  //    measured so far (the prediction's velocity is a step older).
  if (ok) reread_depth(cur, frame);
  if (ok) ok = track_local_map(cur);
  out.features = cur.f;
  out.n_inliers = cur.n_map_matched();
  if (!ok && pending > 0) {  // the map is behind: nothing changed, let the caller retry
    out.deferred = true;
    return out;
  }
  if (!ok) {
    const bool from_rest = state_ == FrameState::kOk && !velocity_;
    if (state_ == FrameState::kOk) reckoner_.start_coasting(velocity_);
    track_lost(cur, frame, from_rest, out);
    return out;
  }
  state_ = FrameState::kOk;
  velocity_ = cur.T_c_w * last_.T_c_w.inverse();
  if (!recent_.empty() && recent_.back().first != prev_frame_t_s_) recent_.clear();
  recent_.emplace_back(frame.t_s, cur.T_c_w);
  if (recent_.size() > 8) recent_.pop_front();
  learn_sensor(cur, frame);
  out.state = state_;
  out.T_w_c = cur.T_c_w.inverse();
  // 5. Keyframe decision (localisation only: a new local map instead of a keyframe).
  const bool want_keyframe = need_keyframe(cur, frame.index, out.n_inliers, pending);
  peak_inliers_ = want_keyframe ? 0 : std::max(peak_inliers_, out.n_inliers);
  if (want_keyframe) {
    if (!localize_only_) {
      out.keyframe = make_request(cur, frame);
    } else {
      out.wants_local_map = true;
      for (int i = 0; i < n; ++i)
        if (cur.matched[i] && cur.pid[i] != kNoId) out.tracked_points.push_back(cur.pid[i]);
    }
  }
  out.ref_kf = ref_kf_;
  out.T_ref_c = T_w_ref_.inverse() * out.T_w_c;
  if (!out.keyframe && config_.anchor_keyframes > 1) out.anchors = weighted_anchors(cur, out.T_w_c);
  // 6. This frame (with fresh visual-odometry points) is the next frame's "last".
  prepare_last_frame(std::move(cur), config_.close_depth_m);
  return out;
}

std::vector<std::pair<KeyframeAnchor, double>> Tracker::weighted_anchors(const Frame& cur,
                                                                         const SE3& T_w_c) const {
  std::vector<std::pair<KeyframeAnchor, double>> out;
  if (!snapshot_) return out;
  std::vector<PointId> inliers;
  for (int i = 0; i < cur.f->size(); ++i)
    if (cur.matched[i] && cur.pid[i] != kNoId) inliers.push_back(cur.pid[i]);
  std::sort(inliers.begin(), inliers.end());
  bool has_ref = false;
  for (const auto& k : snapshot_->keyframes) {
    int n = 0;
    for (PointId p : k.points) n += p != kNoId && std::binary_search(inliers.begin(), inliers.end(), p);
    if (n == 0) continue;
    has_ref |= k.id == ref_kf_;
    out.push_back({{k.id, k.T_w_c.inverse() * T_w_c}, static_cast<double>(n)});
  }
  // A keyframe still waiting for local mapping (threaded) is not in the snapshot: single anchor.
  if (!has_ref) return {};
  std::sort(out.begin(), out.end(), [](const auto& a, const auto& b) {
    return a.second != b.second ? a.second > b.second : a.first.keyframe < b.first.keyframe;
  });
  if (static_cast<int>(out.size()) > config_.anchor_keyframes) out.resize(config_.anchor_keyframes);
  return out;
}

bool Tracker::initialize(Frame& cur, const RgbdFrame& frame, TrackerOutput& out) {
  out.state = FrameState::kNotInitialized;
  if (cur.n_with_depth() < config_.min_init_depth_points) return false;
  cur.T_c_w = SE3::Identity();  // the first keyframe defines the world frame
  state_ = FrameState::kOk;
  out.state = state_;
  out.T_w_c = SE3::Identity();
  out.keyframe = make_request(cur, frame, /*first_of_map=*/true);
  out.ref_kf = ref_kf_;
  prepare_last_frame(std::move(cur), std::numeric_limits<double>::infinity());
  return true;
}

bool Tracker::lacks_close_points(const Frame& cur) const {
  // Close keypoints with depth: tracked vs. could become new points.
  int close_tracked = 0, close_untracked = 0;
  for (int i = 0; i < cur.f->size(); ++i) {
    const float z = cur.f->depth_m[i];
    if (z <= 0 || z > config_.close_depth_m) continue;
    if (cur.matched[i] && cur.pid[i] != kNoId)
      ++close_tracked;
    else
      ++close_untracked;
  }
  return close_tracked < config_.close_tracked_min && close_untracked > config_.close_untracked_min;
}

bool Tracker::need_keyframe(const Frame& cur, int frame_index, int n_inliers, int pending) const {
  if (!snapshot_) return false;
  const int since = frame_index - last_keyframe_frame_;
  if (since < config_.min_frames_between_keyframes) return false;
  // While a keyframe waits for local mapping, its close keypoints are becoming map points the
  // tracker cannot see yet (ORB-SLAM creates them in the tracking thread; here the mapper does),
  // so "few close points tracked" then only means "the snapshot is behind": counting it made
  // threaded mode insert every frame or two after a keyframe another one (see docs/DECISIONS.md,
  // "Keyframe policy"). Single-thread mode never has a keyframe pending, so it is unchanged.
  const bool need_close = pending == 0 && lacks_close_points(cur);
  const double ref = snapshot_->ref_tracked_points;
  const double ratio = snapshot_->n_map_keyframes < 2 ? 0.4 : config_.keyframe_ref_ratio;
  const SE3 T_ref_c = T_w_ref_.inverse() * cur.T_c_w.inverse();
  const bool moved = (config_.keyframe_max_deg > 0 &&
                      rotation_angle_rad(T_ref_c.linear()) > config_.keyframe_max_deg * M_PI / 180.0) ||
                     (config_.keyframe_max_m > 0 && T_ref_c.translation().norm() > config_.keyframe_max_m);
  auto decide = [&](int tracked) {
    const bool failing = tracked < 0.25 * ref;  // under a quarter of the reference's points tracked
    const bool c1a = since >= config_.max_frames_between_keyframes;
    const bool c1b = pending == 0;
    const bool c1c = failing || need_close;
    const bool decayed = tracked < config_.keyframe_decay_ratio * peak_inliers_;
    const bool c2 = (tracked < ratio * ref || need_close || decayed || moved) && tracked > 15;
    // Local mapping is behind: skip ordinary keyframes (tracking stays real-time), but not when
    // tracking is failing — without a new keyframe the map would stop growing exactly where the
    // camera goes and tracking would be lost. The caller then waits for a queue slot (System::track).
    if (pending >= config_.max_pending_keyframes) return failing && c2;
    return (c1a || c1b || c1c) && c2;
  };
  // The pending keyframes' points count as tracked: they are map points as soon as local mapping
  // has them. Counting only the snapshot's, which falls behind the camera while mapping lags, made
  // tracking ask for a keyframe on every frame (bursts of 5, 27 keyframes instead of 9 on the
  // room flight with mapping 10 frames behind; SlamSystem.ThreadedModeSurvivesASlowMapper).
  // More tracked points never turn a "no" into a "yes" once more than 15 are tracked, so they are
  // only matched when the map's alone would ask for one (~1.3 ms a frame otherwise).
  const bool want = decide(n_inliers);
  if (pending_.empty() || (!want && n_inliers > 15)) return want;
  return decide(n_inliers + count_pending_points(cur));
}

KeyFrameRequest Tracker::make_request(const Frame& cur, const RgbdFrame& frame, bool first_of_map) {
  KeyFrameRequest r;
  r.first_of_map = first_of_map;
  r.frame_index = frame.index;
  r.t_s = frame.t_s;
  r.T_w_c = cur.T_c_w.inverse();
  r.features = cur.f;
  r.submap = submap_;
  r.points.assign(cur.f->size(), kNoId);
  for (int i = 0; i < cur.f->size(); ++i)
    if (cur.matched[i]) r.points[i] = cur.pid[i];
  for (const auto& [id, v] : visibility_) r.visibility.push_back(v);
  std::sort(r.visibility.begin(), r.visibility.end(),
            [](const PointVisibility& a, const PointVisibility& b) { return a.id < b.id; });
  visibility_.clear();
  last_keyframe_frame_ = frame.index;
  ref_kf_ = n_requests_++;
  remember_pending(cur, r);
  T_w_ref_ = r.T_w_c;
  return r;
}

void Tracker::remember_pending(const Frame& cur, const KeyFrameRequest& request) {
  // What local mapping's create_points will make of this keyframe (depth_point_keypoints, with the
  // tracker's close depth and the mapper's default count), for the keyframe decision of the frames
  // tracked before its snapshot arrives (ORB-SLAM's tracking thread creates a keyframe's points
  // itself, so there they are tracked at once). Single-thread mode answers before the next frame,
  // so these are never used there.
  PendingKeyFrame p;
  p.id = ref_kf_;
  p.f = cur.f;
  const double depth_limit_m =
      request.first_of_map ? std::numeric_limits<double>::infinity() : config_.close_depth_m;
  for (const auto& [z, i] : depth_point_keypoints(
           *cur.f, [&](int k) { return request.points[k] == kNoId; }, depth_limit_m, pending_new_points_)) {
    const auto& kp = cur.f->keypoints[i];
    p.keypoints.push_back(i);
    p.p_w.push_back(request.T_w_c * camera_.backproject(kp.pt.x, kp.pt.y, z));
  }
  pending_.push_back(std::move(p));
}

void Tracker::prepare_last_frame(Frame cur, double depth_limit_m) {
  // Keep map-point matches; add temporary points from depth for the closest unmatched keypoints
  // (ORB-SLAM's visual-odometry points), so the next frame has enough to match against.
  for (int i = 0; i < cur.f->size(); ++i)
    if (cur.matched[i] && cur.pid[i] == kNoId) cur.matched[i] = 0;  // previous VO match: drop
  const SE3 T_w_c = cur.T_c_w.inverse();
  for (const auto& [z, i] : depth_point_keypoints(
           *cur.f, [&](int k) { return !cur.matched[k]; }, depth_limit_m, kMinVoPoints)) {
    const auto& kp = cur.f->keypoints[i];
    cur.p_w[i] = T_w_c * camera_.backproject(kp.pt.x, kp.pt.y, z);
    cur.matched[i] = 1;
  }
  last_ = std::move(cur);
}

void Tracker::learn_sensor(const Frame& cur, const RgbdFrame& frame) {
  sensor_.add_offset(frame.depth_dt_s);
  const features::FrameFeatures& f = *cur.f;
  for (int i = 0; i < f.size(); ++i)
    if (cur.matched[i] && cur.pid[i] != kNoId && f.has_depth(i))
      sensor_.add(f.depth_m[i], (cur.T_c_w * cur.p_w[i]).z());
}

void Tracker::note_visible(PointId id, int visible, int found) {
  auto& v = visibility_[id];
  v.id = id;
  v.n_visible += visible;
  v.n_found += found;
}

}  // namespace s3m::slam
