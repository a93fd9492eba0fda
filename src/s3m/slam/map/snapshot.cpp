#include <map>
#include <set>

#include "s3m/slam/map/local_map.hpp"

namespace s3m::slam {

LocalMapSnapshot make_snapshot(const Map& map, KeyframeId ref, int max_keyframes) {
  LocalMapSnapshot s;
  s.reference_kf = ref;
  const KeyFrame& ref_kf = map.keyframe(ref);
  s.submap = ref_kf.submap;
  s.n_map_keyframes = map.n_keyframes_in(ref_kf.submap);
  s.ref_tracked_points = ref_kf.n_tracked_points(s.n_map_keyframes <= 2 ? 1 : 2, map.points());
  // 1. Keyframes: ref, its neighbours, then the neighbours' best neighbours and the spanning tree.
  std::vector<KeyframeId> order{ref};
  std::set<KeyframeId> seen{ref};
  auto add = [&](KeyframeId id) {
    if (static_cast<int>(order.size()) < max_keyframes && map.has_keyframe(id) && seen.insert(id).second)
      order.push_back(id);
  };
  for (KeyframeId nb : ref_kf.best_covisible()) add(nb);
  const std::size_t first_ring = order.size();
  for (std::size_t i = 0; i < first_ring; ++i) {
    const KeyFrame& k = map.keyframe(order[i]);
    for (KeyframeId nb : k.best_covisible(10)) add(nb);
    for (KeyframeId c : k.children) add(c);
    if (k.parent != kNoId) add(k.parent);
  }
  // 2. Copies of the keyframes and of every point they observe.
  for (KeyframeId id : order) {
    const KeyFrame& k = map.keyframe(id);
    s.keyframes.push_back({id, k.T_w_c, k.features, k.points});
    for (PointId pid : k.points) {
      if (pid == kNoId || s.point_index.count(pid)) continue;
      const MapPoint& p = map.point(pid);
      s.point_index[pid] = static_cast<int>(s.points.size());
      s.points.push_back({pid, p.p_w, p.descriptor, p.normal_w, p.min_dist_m, p.max_dist_m});
    }
  }
  return s;
}

KeyframeId best_covisible_keyframe(const Map& map, const std::vector<PointId>& points) {
  std::map<KeyframeId, int> votes;
  for (PointId pid : points)
    if (map.has_point(pid))
      for (const auto& [kf, idx] : map.point(pid).observations) ++votes[kf];
  KeyframeId best = kNoId;
  int best_votes = 0;
  for (const auto& [kf, n] : votes)
    if (n > best_votes) best = kf, best_votes = n;
  return best;
}

}  // namespace s3m::slam
