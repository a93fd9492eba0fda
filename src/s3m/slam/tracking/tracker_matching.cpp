// Tracker stages that find correspondences and optimise the pose (see tracker.hpp).
#include <algorithm>

#include "s3m/features/orb_matcher.hpp"
#include "s3m/slam/map/point_fusion.hpp"
#include "s3m/slam/tracking/reloc_pnp.hpp"
#include "s3m/slam/tracking/tracker.hpp"

namespace s3m::slam {

int Tracker::match_last_frame(Frame& cur, double radius_px) {
  const auto& L = *last_.f;
  const auto& pyr = L.pyramid;
  // Forward motion makes points appear at coarser levels, backward at finer ones.
  const Vec3 t_last_cur = (last_.T_c_w * cur.T_c_w.inverse()).translation();
  const double baseline_m = camera_.bf / camera_.fx;
  const bool forward = t_last_cur.z() > baseline_m, backward = t_last_cur.z() < -baseline_m;
  std::vector<features::ProjectionQuery> queries;
  std::vector<int> source;
  for (int i = 0; i < L.size(); ++i) {
    if (!last_.matched[i]) continue;
    const Vec3 p_c = cur.T_c_w * last_.p_w[i];
    if (p_c.z() <= 1e-3) continue;
    const Eigen::Vector2d uv = camera_.project(p_c);
    if (!camera_.in_image(uv.x(), uv.y())) continue;
    const int octave = L.keypoints[i].octave;
    features::ProjectionQuery q;
    q.u = uv.x();
    q.v = uv.y();
    q.u_right = uv.x() - camera_.bf / p_c.z();
    q.min_level = forward ? octave : backward ? 0 : std::max(0, octave - 1);
    q.max_level = forward ? -1 : octave + 1;
    if (backward) q.max_level = octave;
    q.radius_px = radius_px * pyr.scale[octave];
    q.descriptor = L.descriptor(i);
    q.angle_deg = L.keypoints[i].angle;
    queries.push_back(q);
    source.push_back(i);
  }
  features::ProjectionMatchParams params;
  params.ratio = 1.0;
  params.check_orientation = true;
  std::vector<char> taken(cur.f->size(), 0);
  const auto m = features::match_by_projection(*cur.f, queries, params, taken);
  int n = 0;
  for (std::size_t q = 0; q < m.size(); ++q) {
    if (m[q] < 0) continue;
    const int i = source[q];
    cur.pid[m[q]] = last_.pid[i];
    cur.p_w[m[q]] = last_.p_w[i];
    if (snapshot_ && last_.pid[i] != kNoId)
      if (const auto* sp = snapshot_->find(last_.pid[i])) cur.p_w[m[q]] = sp->p_w;
    cur.matched[m[q]] = 1;
    ++n;
  }
  return n;
}

bool Tracker::track_motion_model(Frame& cur, const SE3& velocity) {
  cur.T_c_w = velocity * last_.T_c_w;
  int n = match_last_frame(cur, config_.motion_radius_px);
  if (n < config_.min_motion_matches) {  // fast motion: a wider window
    std::fill(cur.matched.begin(), cur.matched.end(), 0);
    std::fill(cur.pid.begin(), cur.pid.end(), kNoId);
    n = match_last_frame(cur, 2 * config_.motion_radius_px);
  }
  if (n < config_.min_motion_matches) return false;
  return optimize_and_discard(cur) >= config_.min_pose_inliers;
}

bool Tracker::track_reference_keyframe(Frame& cur) {
  if (!snapshot_ || snapshot_->keyframes.empty()) return false;
  const SE3 T_c_w_last = cur.T_c_w;
  // 1. After LOST frames the last pose is dead reckoning, held once coasting ends: as far off as
  //    the camera moved meanwhile. The pose from PnP RANSAC first, no prior trusted: optimised from
  //    the held pose, a frame can be re-acquired with an offset that the rest of the run keeps
  //    (see docs/DECISIONS.md, "Tracking: frames after a wide gap").
  const bool after_lost = state_ == FrameState::kLost;
  if (after_lost && track_reference_keyframe_wide(cur, T_c_w_last)) return true;
  // 2. Brute-force matches of the keyframe's mapped keypoints, optimised from the last pose: right
  //    after the first keyframe or a short gap the last pose is close enough for the robust optimiser.
  if (match_reference_keyframe(cur, kRefRatio, 15) && optimize_and_discard(cur) >= config_.min_pose_inliers)
    return true;
  // 3. After a wide gap (dropped frames, a fast turn, a sparse recording) it is not: the outliers
  //    pull the pose away. When that fails too, the frame goes on as step 2 left it.
  return !after_lost && track_reference_keyframe_wide(cur, T_c_w_last);
}

bool Tracker::track_reference_keyframe_wide(Frame& cur, const SE3& T_c_w_last) {
  // Looser matches, and the pose from PnP RANSAC on them, no prior trusted.
  if (config_.wide_match_ratio <= kRefRatio) return false;
  Frame wide = Frame::unmatched(cur.f, T_c_w_last);
  if (!match_reference_keyframe(wide, config_.wide_match_ratio, config_.min_pose_inliers)) return false;
  const std::optional<SE3> T_c_w = pose_from_matches(wide);
  if (!T_c_w) return false;
  wide.T_c_w = *T_c_w;
  if (optimize_and_discard(wide) < config_.min_pose_inliers) return false;
  cur = std::move(wide);
  return true;
}

bool Tracker::match_reference_keyframe(Frame& cur, double ratio, int min_matches) const {
  const auto& ref = snapshot_->keyframes.front();
  std::vector<int> rows;
  for (int i = 0; i < static_cast<int>(ref.points.size()); ++i)
    if (ref.points[i] != kNoId && snapshot_->find(ref.points[i])) rows.push_back(i);
  if (rows.size() < 15) return false;
  cv::Mat desc(static_cast<int>(rows.size()), 32, CV_8U);
  for (std::size_t r = 0; r < rows.size(); ++r)
    ref.features->descriptors.row(rows[r]).copyTo(desc.row(int(r)));
  const auto matches = features::match_brute_force(desc, cur.f->descriptors, features::kMatchStrict, ratio);
  if (static_cast<int>(matches.size()) < min_matches) return false;
  for (const auto& [r, j] : matches) {
    const PointId pid = ref.points[rows[r]];
    cur.pid[j] = pid;
    cur.p_w[j] = snapshot_->find(pid)->p_w;
    cur.matched[j] = 1;
  }
  return true;
}

std::optional<SE3> Tracker::pose_from_matches(Frame& cur) const {
  std::vector<Vec3> p_w;
  std::vector<Eigen::Vector2d> uv;
  std::vector<int> kp;
  const auto& F = *cur.f;
  for (int i = 0; i < F.size(); ++i) {
    if (!cur.matched[i]) continue;
    p_w.push_back(cur.p_w[i]);
    uv.emplace_back(F.keypoints[i].pt.x, F.keypoints[i].pt.y);
    kp.push_back(i);
  }
  PnpConfig pnp;
  pnp.min_inliers = config_.min_pose_inliers;
  const PnpResult r = solve_pnp_ransac(p_w, uv, without_distortion(camera_), pnp);
  if (!r.success) return std::nullopt;
  // Only the consensus goes on: one wrong match close to the camera outweighs many right ones in
  // the first (robust) round of the pose optimiser.
  std::vector<char> keep(kp.size(), 0);
  for (int k : r.inliers) keep[size_t(k)] = 1;
  for (std::size_t k = 0; k < kp.size(); ++k)
    if (!keep[k]) cur.matched[kp[k]] = 0, cur.pid[kp[k]] = kNoId;
  return r.T_w_c.inverse();
}

bool Tracker::track_local_map(Frame& cur) {
  if (!snapshot_) return optimize_and_discard(cur) >= config_.min_local_inliers;
  const SE3 T_w_c = cur.T_c_w.inverse();
  const auto& pyr = cur.f->pyramid;
  std::vector<char> already(snapshot_->points.size(), 0);
  for (int i = 0; i < cur.f->size(); ++i)
    if (cur.matched[i] && cur.pid[i] != kNoId) {
      const auto it = snapshot_->point_index.find(cur.pid[i]);
      if (it != snapshot_->point_index.end()) already[it->second] = 1;
      note_visible(cur.pid[i], 1, 0);
    }
  // 1. Project every local point that could be visible; 2. match in a window scaled by level.
  std::vector<features::ProjectionQuery> queries;
  std::vector<int> source;
  for (int k = 0; k < static_cast<int>(snapshot_->points.size()); ++k) {
    if (already[k]) continue;
    const auto& p = snapshot_->points[k];
    Visibility vis;
    if (!predict_visibility(p.p_w, p.normal_w, p.min_dist_m, p.max_dist_m, T_w_c, camera_, pyr, vis))
      continue;
    note_visible(p.id, 1, 0);
    features::ProjectionQuery q;
    q.u = vis.uv.x();
    q.v = vis.uv.y();
    q.u_right = vis.u_right;
    q.min_level = std::max(0, vis.level - 1);
    q.max_level = vis.level;
    q.radius_px = config_.local_radius_factor * (vis.view_cos > 0.998 ? 2.5 : 4.0) * pyr.scale[vis.level];
    q.descriptor = p.descriptor.data();
    queries.push_back(q);
    source.push_back(k);
  }
  std::vector<char> taken(cur.matched.begin(), cur.matched.end());
  for (int i = 0; i < cur.f->size(); ++i)  // VO matches may be replaced by real map points
    if (cur.matched[i] && cur.pid[i] == kNoId) taken[i] = 0;
  const auto m = features::match_by_projection(*cur.f, queries, {}, taken);
  for (std::size_t q = 0; q < m.size(); ++q) {
    if (m[q] < 0) continue;
    const auto& p = snapshot_->points[source[q]];
    cur.pid[m[q]] = p.id;
    cur.p_w[m[q]] = p.p_w;
    cur.matched[m[q]] = 1;
  }
  // 3. Final pose with every correspondence; 4. statistics for point culling.
  const int inliers = optimize_and_discard(cur);
  for (int i = 0; i < cur.f->size(); ++i)
    if (cur.matched[i] && cur.pid[i] != kNoId) note_visible(cur.pid[i], 0, 1);
  return inliers >= config_.min_local_inliers;
}

int Tracker::count_pending_points(const Frame& cur) const {
  // The points of keyframes still being mapped, matched by projection into the final pose and
  // counted when they fit it (chi2, as the pose optimiser's inliers). Only counted, not used for
  // the pose: their positions are depth read at one keyframe, not yet refined by local BA, and
  // tracking with them made the kitchen at 30 Hz worse (ATE mean 3.45 -> 3.68 cm over 5 / 6 runs).
  std::vector<char> taken(cur.f->size(), 0);
  for (int i = 0; i < cur.f->size(); ++i) taken[i] = cur.matched[i] && cur.pid[i] != kNoId;
  std::vector<features::ProjectionQuery> queries;
  std::vector<const Vec3*> source;
  for (const auto& p : pending_) {
    const auto& pyr = p.f->pyramid;
    for (std::size_t k = 0; k < p.keypoints.size(); ++k) {
      const Vec3 p_c = cur.T_c_w * p.p_w[k];
      if (p_c.z() <= 1e-3) continue;
      const Eigen::Vector2d uv = camera_.project(p_c);
      if (!camera_.in_image(uv.x(), uv.y())) continue;
      const auto& kp = p.f->keypoints[p.keypoints[k]];
      features::ProjectionQuery q;
      q.u = uv.x();
      q.v = uv.y();
      q.u_right = uv.x() - camera_.bf / p_c.z();
      q.min_level = std::max(0, kp.octave - 1);
      q.max_level = kp.octave + 1;
      q.radius_px = config_.local_radius_factor * 4.0 * pyr.scale[kp.octave];
      q.descriptor = p.f->descriptor(p.keypoints[k]);
      queries.push_back(q);
      source.push_back(&p.p_w[k]);
    }
  }
  const auto m = features::match_by_projection(*cur.f, queries, {}, taken);
  int n = 0;
  for (std::size_t q = 0; q < m.size(); ++q)
    n += m[q] >= 0 &&
         fits_pose(keypoint_observation(*cur.f, m[q], *source[q]), cur.T_c_w, camera_, config_.pose);
  return n;
}

int Tracker::optimize_and_discard(Frame& cur) {
  std::vector<PoseObservation> obs;
  std::vector<int> kp_index;
  const auto& F = *cur.f;
  for (int i = 0; i < F.size(); ++i) {
    if (!cur.matched[i]) continue;
    obs.push_back(keypoint_observation(F, i, cur.p_w[i]));
    kp_index.push_back(i);
  }
  if (obs.size() < 3) return 0;
  const auto res = optimize_pose(obs, cur.T_c_w, camera_, config_.pose);
  cur.T_c_w = res.T_c_w;
  int map_inliers = 0;
  for (std::size_t k = 0; k < obs.size(); ++k) {
    const int i = kp_index[k];
    if (!res.inlier[k]) {
      cur.matched[i] = 0;
      cur.pid[i] = kNoId;
    } else if (cur.pid[i] != kNoId) {
      ++map_inliers;
    }
  }
  return map_inliers;
}

}  // namespace s3m::slam
