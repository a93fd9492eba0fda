// Map correction after a verified loop: pose propagation, duplicate fusion, essential graph.
#include <algorithm>
#include <set>

#include "s3m/slam/loop/loop_closer.hpp"
#include "s3m/slam/map/point_fusion.hpp"

namespace s3m::slam {

namespace {

std::map<KeyframeId, SE3> keyframe_poses(const Map& map) {
  std::map<KeyframeId, SE3> poses;
  for (const auto& [id, kf] : map.keyframes()) poses[id] = kf.T_w_c;
  return poses;
}

// Essential graph (ORB-SLAM) of one sub-map: spanning tree, strong covisibility edges and past
// loop edges keep the shape measured before the correction (T_before); the new loop links carry
// the correction.
std::vector<PoseGraphEdge> essential_graph(const Map& map, int submap,
                                           const std::map<KeyframeId, SE3>& T_before,
                                           const std::vector<std::pair<KeyframeId, KeyframeId>>& old_loops,
                                           const std::set<std::pair<KeyframeId, KeyframeId>>& new_links,
                                           int min_weight) {
  std::vector<PoseGraphEdge> edges;
  std::set<std::pair<KeyframeId, KeyframeId>> added;
  auto member = [&](KeyframeId k) { return map.has_keyframe(k) && map.keyframe(k).submap == submap; };
  auto add = [&](KeyframeId a, KeyframeId b, const SE3& T_w_a, const SE3& T_w_b, bool loop) {
    if (a == b || !member(a) || !member(b)) return;
    if (!added.insert({std::min(a, b), std::max(a, b)}).second) return;
    edges.push_back(relative_edge(int(a), int(b), T_w_a, T_w_b, 1.0, loop));
  };
  for (const auto& [a, b] : new_links) add(a, b, map.keyframe(a).T_w_c, map.keyframe(b).T_w_c, true);
  for (const auto& [id, kf] : map.keyframes()) {
    if (kf.submap != submap) continue;
    if (kf.parent != kNoId && map.has_keyframe(kf.parent))
      add(kf.parent, id, T_before.at(kf.parent), T_before.at(id), false);
    for (const auto& [n, w] : kf.covisibility) {
      if (w >= min_weight && map.has_keyframe(n)) add(id, n, T_before.at(id), T_before.at(n), false);
    }
  }
  for (const auto& [a, b] : old_loops) {
    if (member(a) && member(b)) add(a, b, T_before.at(a), T_before.at(b), true);
  }
  return edges;
}

}  // namespace

LoopCorrection LoopCloser::correct(Map& map, KeyframeId cur_id, const Verified& v) {
  LoopCorrection out;
  out.current_kf = cur_id;
  out.loop_kf = v.loop_kf;
  out.n_matches = int(v.matches.size());
  out.T_w_kf_before = keyframe_poses(map);
  out.T_loop_current = map.keyframe(v.loop_kf).T_w_c.inverse() * v.T_w_cur;

  // 1. Move the current keyframe and its covisible neighbours rigidly onto the loop side.
  std::set<KeyframeId> group{cur_id};
  for (const auto& [n, w] : map.keyframe(cur_id).covisibility) group.insert(n);
  const SE3 correction = v.T_w_cur * map.keyframe(cur_id).T_w_c.inverse();
  std::map<KeyframeId, SE3> corrected;
  std::map<KeyframeId, std::set<KeyframeId>> neighbours_before;
  for (KeyframeId k : group) {
    corrected[k] = correction * map.keyframe(k).T_w_c;
    for (const auto& [n, w] : map.keyframe(k).covisibility) neighbours_before[k].insert(n);
  }
  map.apply_corrected_poses(corrected);

  // 2-4. Fusion, links across the loop, essential graph.
  weld(map, cur_id, v, group, neighbours_before, out.T_w_kf_before, {}, out);
  loop_edges_.emplace_back(cur_id, v.loop_kf);

  // 5. Optional global BA to polish points and poses together.
  if (config_.global_ba) global_bundle_adjustment(map, camera_, config_.ba);
  out.T_w_kf_after = keyframe_poses(map);
  return out;
}

void LoopCloser::weld(Map& map, KeyframeId cur_id, const Verified& v, const std::set<KeyframeId>& group,
                      const std::map<KeyframeId, std::set<KeyframeId>>& neighbours_before,
                      const std::map<KeyframeId, SE3>& T_before, const std::set<KeyframeId>& fixed,
                      LoopCorrection& out) {
  // 2. Fuse duplicates: the current keyframe's matches first (the loop side's point survives,
  //    it is the older, better-observed one), then the loop points projected into the group.
  std::vector<PointId> loop_points;
  for (const auto& [i, pid] : v.matches) {
    if (!map.has_point(pid)) continue;
    loop_points.push_back(pid);
    const PointId own = map.keyframe(cur_id).points[size_t(i)];
    if (own == pid) continue;
    if (own != kNoId && map.has_point(own)) {
      map.replace_point(own, pid);
    } else if (!map.point(pid).observations.count(cur_id)) {
      map.add_observation(pid, cur_id, i);
      map.update_point_appearance(pid);
    }
    ++out.n_fused;
  }
  for (KeyframeId k : group) {
    if (map.has_keyframe(k)) out.n_fused += fuse_points(map, k, loop_points, camera_);
  }

  // 3. New covisibility links across the loop become loop edges of the essential graph.
  std::set<std::pair<KeyframeId, KeyframeId>> new_links{{cur_id, v.loop_kf}};
  for (KeyframeId k : group) {
    if (!map.has_keyframe(k)) continue;
    map.update_covisibility(k);
    for (const auto& [n, w] : map.keyframe(k).covisibility) {
      const auto before = neighbours_before.find(k);
      if (!group.count(n) && (before == neighbours_before.end() || !before->second.count(n)))
        new_links.insert({k, n});
    }
  }

  // 4. Essential-graph optimisation of the current keyframe's sub-map with its oldest keyframe
  //    (and `fixed`) held, then every keyframe (and the points it created) moves to its optimised
  //    pose.
  const int submap = map.keyframe(cur_id).submap;
  const auto edges =
      essential_graph(map, submap, T_before, loop_edges_, new_links, config_.essential_min_weight);
  std::map<int, SE3> nodes;
  for (const auto& [id, kf] : map.keyframes())
    if (kf.submap == submap) nodes[int(id)] = kf.T_w_c;
  std::set<int> held{nodes.begin()->first};
  for (KeyframeId k : fixed)
    if (nodes.count(int(k))) held.insert(int(k));
  optimize_pose_graph(nodes, edges, held, config_.pose_graph);
  std::map<KeyframeId, SE3> optimised;
  for (const auto& [id, T] : nodes) optimised[KeyframeId(id)] = T;
  map.apply_corrected_poses(optimised);
}

}  // namespace s3m::slam
