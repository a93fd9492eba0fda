// Welding bundle adjustment of a merge (loop/map_merge.hpp): the moved sub-map's keyframes at the seam
// are refined on the points both sides now share, every other keyframe held.
#include <algorithm>
#include <map>
#include <set>

#include "s3m/slam/optim/bundle_adjustment.hpp"

namespace s3m::slam {

int weld_bundle_adjustment(Map& map, const std::set<KeyframeId>& window, const PinholeCamera& camera,
                           const BaConfig& config) {
  // 1. The window's keyframes (optimised) and every point they observe.
  BaProblem P;
  std::map<KeyframeId, int> frame_of;
  auto add_frame = [&](KeyframeId id, bool fixed) {
    frame_of[id] = int(P.T_c_w.size());
    P.T_c_w.push_back(map.keyframe(id).T_w_c.inverse());
    P.fixed.push_back(fixed ? 1 : 0);
  };
  for (KeyframeId id : window)
    if (map.has_keyframe(id)) add_frame(id, false);
  std::map<PointId, int> point_of;
  std::vector<PointId> point_ids;
  for (KeyframeId id : window)
    if (map.has_keyframe(id))
      for (PointId pid : map.keyframe(id).points)
        if (pid != kNoId && !point_of.count(pid)) {
          point_of[pid] = int(P.p_w.size());
          P.p_w.push_back(map.point(pid).p_w);
          point_ids.push_back(pid);
        }
  // 2. Every observation of those points; keyframes outside the window (the older map's among
  //    them) are held where they are.
  std::vector<std::pair<PointId, KeyframeId>> keys;
  for (PointId pid : point_ids)
    for (const auto& [kf, idx] : map.point(pid).observations) {
      if (!frame_of.count(kf)) add_frame(kf, true);
      P.obs.push_back(
          keypoint_ba_observation(*map.keyframe(kf).features, idx, frame_of.at(kf), point_of.at(pid)));
      keys.emplace_back(pid, kf);
    }
  if (P.obs.empty() || std::count(P.fixed.begin(), P.fixed.end(), 1) == 0) return 0;
  // 3. Solve; erase outlier observations; write back.
  const BaResult r = bundle_adjust(P, camera, config);
  if (!r.converged) return 0;
  for (std::size_t k = 0; k < P.obs.size(); ++k)
    if (r.outlier[k] && map.has_point(keys[k].first)) map.erase_observation(keys[k].first, keys[k].second);
  for (const auto& [id, f] : frame_of)
    if (!P.fixed[size_t(f)]) map.set_keyframe_pose(id, P.T_c_w[size_t(f)].inverse());
  for (std::size_t i = 0; i < point_ids.size(); ++i)
    if (map.has_point(point_ids[i])) {
      map.set_point_position(point_ids[i], P.p_w[i]);
      map.update_point_appearance(point_ids[i]);
    }
  return r.n_outliers;
}

}  // namespace s3m::slam
