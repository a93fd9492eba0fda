// Local bundle adjustment over the covisibility window of a keyframe (see bundle_adjustment.hpp).
#include <cmath>
#include <map>

#include "s3m/slam/optim/bundle_adjustment.hpp"

namespace s3m::slam {

LocalBaStats local_bundle_adjustment(Map& map, KeyframeId kf_id, const PinholeCamera& camera,
                                     const BaConfig& config) {
  LocalBaStats st;
  // 1. The window: the keyframe and its strongest covisible neighbours.
  std::map<KeyframeId, int> frame_index;  // keyframe -> BaProblem frame
  BaProblem P;
  auto add_frame = [&](KeyframeId id, bool fixed) {
    frame_index[id] = static_cast<int>(P.T_c_w.size());
    P.T_c_w.push_back(map.keyframe(id).T_w_c.inverse());
    P.fixed.push_back(fixed ? 1 : 0);
  };
  // A sub-map's root keyframe defines its world and is never moved (as ORB-SLAM holds keyframe
  // 0): free in a window with fixed neighbours, it drifts with the window and takes the whole
  // trajectory's origin with it (see docs/DECISIONS.md, "Local BA: keyframes held where they were").
  add_frame(kf_id, map.keyframe(kf_id).is_root());
  for (KeyframeId nb : map.keyframe(kf_id).best_covisible(config.max_local_keyframes - 1))
    add_frame(nb, map.keyframe(nb).is_root());
  st.n_local_keyframes = static_cast<int>(frame_index.size());
  // 2. Points seen by the window; 3. the other keyframes that see them are held fixed.
  std::map<PointId, int> point_index;
  std::vector<PointId> point_ids;
  for (const auto& [id, f] : std::map<KeyframeId, int>(frame_index))
    for (PointId pid : map.keyframe(id).points)
      if (pid != kNoId && !point_index.count(pid)) {
        point_index[pid] = static_cast<int>(P.p_w.size());
        P.p_w.push_back(map.point(pid).p_w);
        point_ids.push_back(pid);
      }
  std::vector<std::pair<PointId, KeyframeId>> obs_keys;
  for (PointId pid : point_ids)
    for (const auto& [kf, idx] : map.point(pid).observations) {
      if (!frame_index.count(kf)) add_frame(kf, true);
      P.obs.push_back(
          keypoint_ba_observation(*map.keyframe(kf).features, idx, frame_index.at(kf), point_index.at(pid)));
      obs_keys.emplace_back(pid, kf);
    }
  st.n_fixed_keyframes = static_cast<int>(P.T_c_w.size()) - st.n_local_keyframes;
  // The gauge: with no fixed neighbour (start of the map) hold the oldest keyframe.
  if (st.n_fixed_keyframes == 0) P.fixed[frame_index.begin()->second] = 1;
  st.n_points = static_cast<int>(P.p_w.size());
  st.n_observations = static_cast<int>(P.obs.size());

  // 4. Solve; keyframes moved too far are held and the window solved again. 5. Erase outlier
  //    observations, write back poses and points.
  const BaProblem before = P;
  BaResult res = bundle_adjust(P, camera, config);
  if (!res.converged) return st;
  st.n_held_keyframes = hold_keyframes_moved_too_far(before, P, config);
  if (st.n_held_keyframes > 0) {
    const std::vector<char> held = P.fixed;
    P = before;
    P.fixed = held;
    res = bundle_adjust(P, camera, config);
    if (!res.converged) return st;
  }
  for (std::size_t k = 0; k < P.obs.size(); ++k)
    if (res.outlier[k] && map.has_point(obs_keys[k].first)) {
      map.erase_observation(obs_keys[k].first, obs_keys[k].second);
      ++st.n_outliers;
    }
  for (const auto& [id, f] : frame_index)
    if (!P.fixed[f]) map.set_keyframe_pose(id, P.T_c_w[f].inverse());
  for (std::size_t i = 0; i < point_ids.size(); ++i)
    if (map.has_point(point_ids[i])) {
      map.set_point_position(point_ids[i], P.p_w[i]);
      map.update_point_appearance(point_ids[i]);
    }
  return st;
}

}  // namespace s3m::slam
