#include "s3m/slam/loop/loop_closer.hpp"

#include <algorithm>

#include "s3m/core/error.hpp"
#include "s3m/features/orb_matcher.hpp"
#include "s3m/slam/map/group_search.hpp"

namespace s3m::slam {

void LoopConfig::validate() const {
  require(min_keyframes >= 1 && min_keyframes <= 100000,
          "loop_closing.min_keyframes must be in 1..100000 (got " + std::to_string(min_keyframes) + ")");
  require(min_keyframes_since_loop >= 0, "loop_closing.min_keyframes_since_loop must be >= 0");
  require(direct_level >= 0, "loop_closing.direct_level must be >= 0");
  detector.validate();
  bow_match.validate();
  ransac.validate();
  require(min_bow_matches >= 3 && min_projection_matches >= 3,
          "loop_closing: min_bow_matches and min_projection_matches must be >= 3");
  require(loop_group_size >= 0 && search_radius_factor > 0,
          "loop_closing: loop_group_size must be >= 0, search_radius_factor > 0");
  require(essential_min_weight >= 0, "loop_closing.essential_min_weight must be >= 0");
  pose_graph.validate();
  ba.validate();
  merge.validate();
}

LoopCloser::LoopCloser(std::shared_ptr<const features::Vocabulary> vocabulary, const PinholeCamera& camera,
                       const LoopConfig& config)
    : camera_(camera),
      config_(config),
      index_(std::move(vocabulary), config.direct_level),
      detector_(config.detector) {
  config_.validate();
}

std::optional<LoopCorrection> LoopCloser::process(Map& map, KeyframeId kf) {
  // 1. Keep the BoW index in step with the map (new keyframe in, culled keyframes out).
  index_.sync(map);
  if (!map.has_keyframe(kf) || !index_.find(kf)) return std::nullopt;
  if (map.n_keyframes() < config_.min_keyframes) return std::nullopt;
  if (last_loop_kf_ != kNoId && kf - last_loop_kf_ < config_.min_keyframes_since_loop) return std::nullopt;
  // 2. Candidates that have been consistent for several keyframes.
  const std::vector<KeyframeId> candidates = detector_.detect(map, index_, kf);
  if (candidates.empty()) return std::nullopt;
  // 3. Geometric verification: candidates in another sub-map first (a merge, map_merge.cpp), then
  //    loops within the keyframe's own sub-map.
  std::vector<KeyframeId> same, other;
  for (KeyframeId c : candidates)
    (map.keyframe(c).submap == map.keyframe(kf).submap ? same : other).push_back(c);
  std::optional<LoopCorrection> correction = other.empty() ? std::nullopt : merge_at(map, kf, other);
  if (!correction) {
    const auto verified = same.empty() ? std::nullopt : verify(map, kf, same);
    if (!verified) return std::nullopt;
    // 4-6. Correction, fusion, pose graph, optional global BA.
    correction = correct(map, kf, *verified);
  }
  detector_.reset();
  last_loop_kf_ = kf;
  return correction;
}

std::optional<SE3> LoopCloser::ransac_with_bow(const Map& map, KeyframeId cur_id, KeyframeId cand_id) const {
  const KeyFrame& cur = map.keyframe(cur_id);
  const KeyFrame& cand = map.keyframe(cand_id);
  std::vector<bool> has_point(cand.points.size());
  for (size_t j = 0; j < cand.points.size(); ++j)
    has_point[j] = cand.points[j] != kNoId && map.has_point(cand.points[j]);
  const auto matches = features::match_by_bow(index_.find(cur_id)->direct, cur.features->descriptors,
                                              index_.find(cand_id)->direct, cand.features->descriptors,
                                              config_.bow_match, has_point);
  if (int(matches.size()) < config_.min_bow_matches) return std::nullopt;
  // Candidate side: its map points in its camera frame; current side: own map point if any, else
  // the keypoint's depth.
  const SE3 T_cand_w = cand.T_w_c.inverse(), T_cur_w = cur.T_w_c.inverse();
  std::vector<Vec3> p_cand, p_cur;
  for (const auto& [i, j] : matches) {
    const Vec3 a = T_cand_w * map.point(cand.points[size_t(j)]).p_w;
    const PointId own = cur.points[size_t(i)];
    if (own != kNoId && map.has_point(own)) {
      p_cur.push_back(T_cur_w * map.point(own).p_w);
    } else if (cur.features->has_depth(i)) {
      const auto& kp = cur.features->keypoints[size_t(i)];
      p_cur.push_back(camera_.backproject(kp.pt.x, kp.pt.y, cur.features->depth_m[size_t(i)]));
    } else {
      continue;
    }
    p_cand.push_back(a);
  }
  const Se3RansacResult r = estimate_se3_ransac(p_cand, p_cur, config_.ransac);
  if (!r.success) return std::nullopt;
  return cand.T_w_c * r.T_a_b;  // T_w_cur as seen from the loop side
}

std::vector<std::pair<int, PointId>> LoopCloser::search_loop_group(const Map& map, KeyframeId cur_id,
                                                                   KeyframeId loop_kf,
                                                                   const SE3& T_w_cur) const {
  GroupSearchParams p;
  p.group_size = config_.loop_group_size;
  p.radius_factor = config_.search_radius_factor;
  p.levels_above = 0;
  p.max_distance = features::kMatchStrict;
  p.skip_observed_by = cur_id;  // already linked to the current keyframe: not loop evidence
  return match_covisible_group(*map.keyframe(cur_id).features, map, loop_kf, T_w_cur, camera_, p);
}

std::optional<LoopCloser::Verified> LoopCloser::verify(const Map& map, KeyframeId cur_id,
                                                       const std::vector<KeyframeId>& candidates,
                                                       VerifyStats* stats) const {
  const KeyFrame& cur = map.keyframe(cur_id);
  VerifyStats none;
  VerifyStats& st = stats ? *stats : none;
  for (KeyframeId cand : candidates) {
    ++st.candidates;
    // 1. BoW matches -> SE3 by 3D-3D RANSAC.
    const auto T_w_cur = ransac_with_bow(map, cur_id, cand);
    if (!T_w_cur) continue;
    ++st.bow_matched;
    // 2. Guided search for the loop group's points with that pose.
    auto matches = search_loop_group(map, cur_id, cand, *T_w_cur);
    st.best_matches = std::max(st.best_matches, int(matches.size()));
    if (int(matches.size()) < config_.min_projection_matches) continue;
    // 3. Refine on every match with depth: loop-group points (world, loop side) vs the current
    //    keyframe's back-projected keypoints, then search again with the refined pose.
    std::vector<Vec3> p_w, p_c;
    for (const auto& [i, pid] : matches) {
      if (!cur.features->has_depth(i)) continue;
      const auto& kp = cur.features->keypoints[size_t(i)];
      p_c.push_back(camera_.backproject(kp.pt.x, kp.pt.y, cur.features->depth_m[size_t(i)]));
      p_w.push_back(map.point(pid).p_w);
    }
    const Se3RansacResult refined = estimate_se3_ransac(p_w, p_c, config_.ransac);
    Verified v;
    v.loop_kf = cand;
    v.T_w_cur = refined.success ? refined.T_a_b : *T_w_cur;
    v.matches = search_loop_group(map, cur_id, cand, v.T_w_cur);
    st.best_matches = std::max(st.best_matches, int(v.matches.size()));
    if (int(v.matches.size()) < config_.min_projection_matches) continue;
    return v;
  }
  return std::nullopt;
}

}  // namespace s3m::slam
