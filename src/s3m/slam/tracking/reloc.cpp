#include "s3m/slam/tracking/reloc.hpp"

#include <algorithm>

#include "s3m/core/error.hpp"
#include "s3m/features/orb_matcher.hpp"
#include "s3m/slam/map/group_search.hpp"
#include "s3m/slam/optim/pose_optimizer.hpp"

namespace s3m::slam {

void RelocConfig::validate() const {
  require(max_candidates >= 1, "loop_closing.reloc.max_candidates must be >= 1");
  require(min_score_ratio > 0 && min_score_ratio <= 1,
          "loop_closing.reloc.min_score_ratio must be in (0, 1]");
  bow_match.validate();
  pnp.validate();
  require(min_bow_matches >= 4 && min_final_inliers >= 4,
          "loop_closing.reloc: min_bow_matches and min_final_inliers must be >= 4");
  require(local_keyframes >= 0 && search_radius_factor > 0 && wide_radius_factor > 0,
          "loop_closing.reloc: local_keyframes must be >= 0, wide_/search_radius_factor > 0");
  require(snapshot_keyframes >= 1, "loop_closing.reloc.snapshot_keyframes must be >= 1");
}

namespace {

// Points of keyframe kf and its covisible neighbours projected into the frame at T_w_c and
// matched by descriptor; returns (keypoint, point) pairs, including the seed matches.
std::vector<std::pair<int, PointId>> guided_matches(const features::FrameFeatures& f, const Map& map,
                                                    KeyframeId kf, const SE3& T_w_c,
                                                    const PinholeCamera& camera, const RelocConfig& config,
                                                    double radius_factor) {
  // The pose is a RANSAC estimate, so the window is wide and the descriptor bound loose (ORB-SLAM
  // uses its TH_HIGH here); the final PnP rejects what does not fit.
  GroupSearchParams p;
  p.group_size = config.local_keyframes;
  p.radius_factor = radius_factor;
  p.levels_above = 1;
  p.max_distance = features::kMatchLoose;
  return match_covisible_group(f, map, kf, T_w_c, camera, p);
}

// Pose-only optimisation with the stereo-like RGB-D residual (u, v, u_right): the depth term pins
// down the sideways-translation / rotation ambiguity that PnP has on distant, near-planar points.
PoseOptimizerResult refine(const features::FrameFeatures& f, const Map& map,
                           const std::vector<std::pair<int, PointId>>& m, const SE3& T_w_c,
                           const PinholeCamera& camera) {
  std::vector<PoseObservation> obs;
  for (const auto& [i, pid] : m) obs.push_back(keypoint_observation(f, i, map.point(pid).p_w));
  return optimize_pose(obs, T_w_c.inverse(), camera);
}

PnpResult pnp(const features::FrameFeatures& f, const Map& map, const std::vector<std::pair<int, PointId>>& m,
              const PinholeCamera& camera, const PnpConfig& config) {
  std::vector<Vec3> p_w;
  std::vector<Eigen::Vector2d> uv;
  for (const auto& [i, pid] : m) {
    p_w.push_back(map.point(pid).p_w);
    uv.emplace_back(f.keypoints[size_t(i)].pt.x, f.keypoints[size_t(i)].pt.y);
  }
  return solve_pnp_ransac(p_w, uv, camera, config);
}

}  // namespace

RelocResult relocalise(const features::FrameFeatures& f, const Map& map, const KeyFrameBowIndex& index,
                       const PinholeCamera& camera_in, const RelocConfig& config, int submap) {
  config.validate();
  RelocResult result;
  if (f.size() == 0 || index.size() == 0) return result;
  const PinholeCamera camera = without_distortion(camera_in);
  // 1-2. BoW of the frame and the best-scoring keyframes.
  const KeyFrameBow q = index.describe(f.descriptors);
  const auto hits = index.database().query(q.bow, 0, [&](int id) {
    return map.has_keyframe(KeyframeId(id)) && (submap < 0 || map.keyframe(KeyframeId(id)).submap == submap);
  });
  if (hits.empty()) return result;
  for (const auto& h : hits) {
    if (result.n_candidates >= config.max_candidates || h.score < config.min_score_ratio * hits[0].score)
      break;
    const KeyframeId kf_id = KeyframeId(h.entry_id);
    const KeyFrame& kf = map.keyframe(kf_id);
    const KeyFrameBow* kb = index.find(kf_id);
    if (!kb) continue;
    ++result.n_candidates;
    // 3. BoW matches against the candidate's map points.
    std::vector<bool> has_point(kf.points.size());
    for (size_t j = 0; j < kf.points.size(); ++j)
      has_point[j] = kf.points[j] != kNoId && map.has_point(kf.points[j]);
    std::vector<std::pair<int, PointId>> seed;
    for (const auto& [i, j] : features::match_by_bow(q.direct, f.descriptors, kb->direct,
                                                     kf.features->descriptors, config.bow_match, has_point))
      seed.emplace_back(i, kf.points[size_t(j)]);
    if (int(seed.size()) < config.min_bow_matches) continue;
    // 4. PnP RANSAC on the seed matches, then pose-only optimisation with depth.
    PnpConfig first = config.pnp;
    first.min_inliers = std::min(first.min_inliers, config.min_bow_matches);
    const PnpResult initial = pnp(f, map, seed, camera, first);
    if (!initial.success) continue;
    std::vector<std::pair<int, PointId>> seed_inliers;
    for (int k : initial.inliers) seed_inliers.push_back(seed[size_t(k)]);
    PoseOptimizerResult opt = refine(f, map, seed_inliers, initial.T_w_c, camera);
    if (opt.n_inliers < std::min(10, config.min_bow_matches)) continue;
    // 5. More matches from the candidate's local map: a wide window around that pose, then a
    //    narrow one around the refined pose (ORB-SLAM's two projection passes).
    for (double radius : {config.wide_radius_factor, config.search_radius_factor}) {
      const auto all = guided_matches(f, map, kf_id, opt.T_c_w.inverse(), camera, config, radius);
      if (int(all.size()) < config.min_final_inliers) {
        opt.n_inliers = 0;
        break;
      }
      opt = refine(f, map, all, opt.T_c_w.inverse(), camera);
    }
    if (opt.n_inliers < config.min_final_inliers) continue;
    result.success = true;
    result.T_w_c = opt.T_c_w.inverse();
    result.keyframe = kf_id;
    result.n_inliers = opt.n_inliers;
    return result;
  }
  return result;
}

}  // namespace s3m::slam
