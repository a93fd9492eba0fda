// Sub-maps of the Map: a session that cannot relocalise starts a new sub-map in a
// frame of its own; merging moves it into an older one (map_merge.cpp). These are the Map's
// bookkeeping for that: membership, the rigid move, the spanning tree across the seam, pruning
// what never joined the world, and copying a second saved map in for the offline merge.
#include <algorithm>

#include "s3m/core/error.hpp"
#include "s3m/slam/map/map.hpp"

namespace s3m::slam {

int Map::submap_of(KeyframeId id) const {
  const auto it = keyframes_.find(id);
  if (it != keyframes_.end()) return it->second.submap;
  const auto c = culled_.find(id);
  require(c != culled_.end(), "Map::submap_of: unknown keyframe id " + std::to_string(id));
  return submap_of(c->second.first);  // a culled keyframe belongs where its parent does
}

int Map::n_keyframes_in(int submap) const {
  return static_cast<int>(std::count_if(keyframes_.begin(), keyframes_.end(),
                                        [&](const auto& kv) { return kv.second.submap == submap; }));
}

void Map::move_submap(int from, int to, const SE3& T_to_from) {
  require(from != to, "Map::move_submap: a sub-map cannot be merged into itself");
  // Points move with their reference keyframe; a point's keyframes all share its sub-map (sub-maps
  // share no points before they are merged).
  for (auto& [pid, p] : points_)
    if (keyframes_.at(p.ref_kf).submap == from) {
      p.p_w = T_to_from * p.p_w;
      p.normal_w = T_to_from.linear() * p.normal_w;
    }
  for (auto& [id, kf] : keyframes_)
    if (kf.submap == from) {
      kf.T_w_c = T_to_from * kf.T_w_c;
      kf.submap = to;
    }
}

void Map::swap_submaps(int a, int b) {
  for (auto& [id, kf] : keyframes_)  // culled keyframes follow their parents (submap_of)
    if (kf.submap == a || kf.submap == b) kf.submap = kf.submap == a ? b : a;
}

std::map<KeyframeId, SE3> Map::culled_poses_in(int submap) const {
  std::map<KeyframeId, SE3> poses;
  for (const auto& [id, link] : culled_)
    if (submap_of(id) == submap) poses.emplace(id, resolve_T_w_kf(id));
  return poses;
}

void Map::join_tree(KeyframeId kf, KeyframeId new_parent) {
  require(keyframes_.count(kf) && keyframes_.count(new_parent) && kf != new_parent,
          "Map::join_tree: needs two different live keyframes");
  KeyframeId prev = new_parent, cur = kf;
  while (cur != kNoId) {
    KeyFrame& k = keyframes_.at(cur);
    const KeyframeId next = k.parent;
    if (next != kNoId) keyframes_.at(next).children.erase(cur);
    k.parent = prev;
    keyframes_.at(prev).children.insert(cur);
    k.children.erase(prev);
    prev = cur;
    cur = next;
  }
}

void Map::keep_only_submap(int submap) {
  std::vector<KeyframeId> gone;
  for (const auto& [id, kf] : keyframes_)
    if (kf.submap != submap) gone.push_back(id);
  if (gone.empty()) return;
  for (KeyframeId id : gone) {
    for (PointId pid : std::vector<PointId>(keyframes_.at(id).points))
      if (pid != kNoId && points_.count(pid)) erase_observation(pid, id);
    for (const auto& [nb, w] : keyframes_.at(id).covisibility)
      if (keyframes_.count(nb)) keyframes_.at(nb).covisibility.erase(id);
  }
  for (KeyframeId id : gone) keyframes_.erase(id);
  // Culled keyframes whose chain ended in an erased one do not resolve any more.
  for (bool changed = true; changed;) {
    changed = false;
    for (auto it = culled_.begin(); it != culled_.end();)
      if (!keyframes_.count(it->second.first) && !culled_.count(it->second.first)) {
        it = culled_.erase(it);
        changed = true;
      } else {
        ++it;
      }
  }
}

KeyframeId Map::append(const Map& other, int submap) {
  const KeyframeId kf_offset = next_kf_id_;
  const PointId pt_offset = next_point_id_;
  auto kf_id = [&](KeyframeId id) { return id == kNoId ? kNoId : id + kf_offset; };
  for (const auto& [id, src] : other.keyframes_) {
    KeyFrame kf = src;
    kf.id = kf_id(id);
    kf.submap = submap;
    kf.parent = kf_id(src.parent);
    for (PointId& p : kf.points)
      if (p != kNoId) p += pt_offset;
    kf.covisibility.clear();
    for (const auto& [nb, w] : src.covisibility) kf.covisibility[kf_id(nb)] = w;
    kf.children.clear();
    for (KeyframeId c : src.children) kf.children.insert(kf_id(c));
    keyframes_.emplace(kf.id, std::move(kf));
  }
  for (const auto& [id, src] : other.points_) {
    MapPoint p = src;
    p.id = id + pt_offset;
    p.ref_kf = kf_id(src.ref_kf);
    p.observations.clear();
    for (const auto& [k, idx] : src.observations) p.observations[kf_id(k)] = idx;
    points_.emplace(p.id, std::move(p));
  }
  for (const auto& [id, link] : other.culled_) culled_[kf_id(id)] = {kf_id(link.first), link.second};
  next_kf_id_ += other.next_kf_id_;
  next_point_id_ += other.next_point_id_;
  return kf_offset;
}

}  // namespace s3m::slam
