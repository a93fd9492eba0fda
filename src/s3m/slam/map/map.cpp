#include "s3m/slam/map/map.hpp"

#include <algorithm>
#include <cmath>
#include <iterator>

#include "s3m/core/error.hpp"
#include "s3m/features/orb_matcher.hpp"

namespace s3m::slam {
namespace {

constexpr int kCovisibilityMinWeight = 15;  // shared points for a covisibility edge (ORB-SLAM)

const std::uint8_t* kf_descriptor(const KeyFrame& kf, int idx) { return kf.features->descriptor(idx); }

}  // namespace

std::vector<KeyframeId> KeyFrame::best_covisible(int n, int min_weight) const {
  std::vector<std::pair<int, KeyframeId>> v;
  for (const auto& [id, w] : covisibility)
    if (w >= min_weight) v.emplace_back(-w, id);
  std::sort(v.begin(), v.end());
  std::vector<KeyframeId> out;
  for (const auto& p : v) {
    if (n >= 0 && static_cast<int>(out.size()) >= n) break;
    out.push_back(p.second);
  }
  return out;
}

int KeyFrame::n_tracked_points(int min_obs, const std::map<PointId, MapPoint>& pts) const {
  int n = 0;
  for (PointId pid : points)
    if (pid != kNoId && static_cast<int>(pts.at(pid).observations.size()) >= min_obs) ++n;
  return n;
}

int predict_level(double dist_m, double max_dist_m, const features::ScalePyramid& pyr) {
  const double ratio = max_dist_m / std::max(dist_m, 1e-9);
  const int level = static_cast<int>(std::ceil(std::log(ratio) / pyr.log_scale_factor));
  return std::clamp(level, 0, pyr.n_levels() - 1);
}

KeyframeId Map::add_keyframe(KeyFrame kf) {
  require(kf.features != nullptr && static_cast<int>(kf.points.size()) == kf.features->size(),
          "Map::add_keyframe: keyframe needs features and one point slot per keypoint");
  kf.id = next_kf_id_++;
  kf.covisibility.clear();
  kf.children.clear();
  kf.parent = kNoId;
  const KeyframeId id = kf.id;
  std::vector<PointId> slots = std::move(kf.points);
  kf.points.assign(slots.size(), kNoId);
  keyframes_.emplace(id, std::move(kf));
  for (int i = 0; i < static_cast<int>(slots.size()); ++i)
    if (slots[i] != kNoId && points_.count(slots[i]) && !points_.at(slots[i]).observations.count(id))
      add_observation(slots[i], id, i);
  return id;
}

PointId Map::add_point(const Vec3& p_w, KeyframeId kf, int idx) {
  MapPoint p;
  p.id = next_point_id_++;
  p.p_w = p_w;
  p.ref_kf = kf;
  const PointId id = p.id;
  points_.emplace(id, std::move(p));
  add_observation(id, kf, idx);
  update_point_appearance(id);
  return id;
}

void Map::add_observation(PointId pid, KeyframeId kf, int idx) {
  auto& k = keyframes_.at(kf);
  require(k.points[idx] == kNoId || k.points[idx] == pid,
          "Map::add_observation: keypoint slot already taken");
  k.points[idx] = pid;
  points_.at(pid).observations[kf] = idx;
}

void Map::erase_observation(PointId pid, KeyframeId kf) {
  auto& p = points_.at(pid);
  const auto it = p.observations.find(kf);
  if (it == p.observations.end()) return;
  keyframes_.at(kf).points[it->second] = kNoId;
  p.observations.erase(it);
  if (p.observations.empty()) {
    points_.erase(pid);
    return;
  }
  if (p.ref_kf == kf) p.ref_kf = p.observations.begin()->first;
}

void Map::replace_point(PointId old_id, PointId keep_id) {
  if (old_id == keep_id) return;
  MapPoint old = std::move(points_.at(old_id));
  points_.erase(old_id);
  auto& keep = points_.at(keep_id);
  for (const auto& [kf, idx] : old.observations) {
    auto& k = keyframes_.at(kf);
    k.points[idx] = kNoId;
    if (!keep.observations.count(kf)) {
      k.points[idx] = keep_id;
      keep.observations[kf] = idx;
    }
  }
  keep.n_visible += old.n_visible;
  keep.n_found += old.n_found;
  update_point_appearance(keep_id);
}

void Map::erase_point(PointId pid) {
  const auto it = points_.find(pid);
  if (it == points_.end()) return;
  for (const auto& [kf, idx] : it->second.observations) keyframes_.at(kf).points[idx] = kNoId;
  points_.erase(it);
}

void Map::erase_keyframe(KeyframeId id) {
  KeyFrame& kf = keyframes_.at(id);
  require(!kf.is_root(), "Map::erase_keyframe: the root keyframe cannot be erased");
  for (PointId pid : std::vector<PointId>(kf.points))
    if (pid != kNoId) erase_observation(pid, id);
  for (const auto& [nb, w] : kf.covisibility) keyframes_.at(nb).covisibility.erase(id);
  auto& parent = keyframes_.at(kf.parent);
  parent.children.erase(id);
  for (KeyframeId c : kf.children) {
    keyframes_.at(c).parent = kf.parent;
    parent.children.insert(c);
  }
  culled_[id] = {kf.parent, parent.T_w_c.inverse() * kf.T_w_c};
  keyframes_.erase(id);
}

void Map::update_covisibility(KeyframeId id) {
  KeyFrame& kf = keyframes_.at(id);
  std::map<KeyframeId, int> counts;
  for (PointId pid : kf.points) {
    if (pid == kNoId) continue;
    for (const auto& [other, idx] : points_.at(pid).observations)
      if (other != id) ++counts[other];
  }
  std::map<KeyframeId, int> edges;
  KeyframeId best = kNoId;
  int best_w = 0;
  for (const auto& [other, w] : counts) {
    if (w >= kCovisibilityMinWeight) edges[other] = w;
    if (w > best_w) best = other, best_w = w;
  }
  if (edges.empty() && best != kNoId) edges[best] = best_w;  // stay connected to the graph
  for (const auto& [other, w] : kf.covisibility)
    if (!edges.count(other)) keyframes_.at(other).covisibility.erase(id);
  for (const auto& [other, w] : edges) keyframes_.at(other).covisibility[id] = w;
  kf.covisibility = std::move(edges);
  if (kf.parent != kNoId) return;
  for (KeyframeId nb : kf.best_covisible())
    if (nb < id && keyframes_.at(nb).submap == kf.submap) {
      kf.parent = nb;
      keyframes_.at(nb).children.insert(id);
      return;
    }
  // No older neighbour: hang it on the previous keyframe of its sub-map. The first keyframe of a
  // sub-map (of the map) stays a root.
  for (auto it = std::make_reverse_iterator(keyframes_.find(id)); it != keyframes_.rend(); ++it)
    if (it->second.submap == kf.submap) {
      kf.parent = it->first;
      it->second.children.insert(id);
      return;
    }
}

void Map::update_point_appearance(PointId pid) {
  MapPoint& p = points_.at(pid);
  // 1. Descriptor with the least median distance to the others.
  std::vector<const std::uint8_t*> descs;
  Vec3 normal = Vec3::Zero();
  for (const auto& [kf_id, idx] : p.observations) {
    const KeyFrame& kf = keyframes_.at(kf_id);
    descs.push_back(kf_descriptor(kf, idx));
    normal += (p.p_w - kf.T_w_c.translation()).normalized();
  }
  const int n = static_cast<int>(descs.size());
  int best = 0, best_median = 1 << 30;
  for (int i = 0; i < n && n > 2; ++i) {
    std::vector<int> d;
    for (int j = 0; j < n; ++j)
      if (j != i) d.push_back(features::descriptor_distance(descs[i], descs[j]));
    std::nth_element(d.begin(), d.begin() + d.size() / 2, d.end());
    if (d[d.size() / 2] < best_median) best_median = d[d.size() / 2], best = i;
  }
  std::copy(descs[best], descs[best] + 32, p.descriptor.begin());
  // 2. Viewing direction and scale-invariance distance range from the reference keyframe.
  p.normal_w = normal.normalized();
  const KeyFrame& ref = keyframes_.at(p.ref_kf);
  const double dist = (p.p_w - ref.T_w_c.translation()).norm();
  const auto& pyr = ref.features->pyramid;
  const int level = ref.features->keypoints[p.observations.at(p.ref_kf)].octave;
  p.max_dist_m = dist * pyr.scale[level];
  p.min_dist_m = p.max_dist_m / pyr.scale.back();
}

void Map::count_visible(PointId pid, int n_visible, int n_found) {
  const auto it = points_.find(pid);
  if (it == points_.end()) return;
  it->second.n_visible += n_visible;
  it->second.n_found += n_found;
}

void Map::apply_corrected_poses(const std::map<KeyframeId, SE3>& T_w_c_corrected) {
  for (auto& [pid, p] : points_) {
    const auto it = T_w_c_corrected.find(p.ref_kf);
    if (it == T_w_c_corrected.end()) continue;
    p.p_w = it->second * (keyframes_.at(p.ref_kf).T_w_c.inverse() * p.p_w);
  }
  for (const auto& [id, T] : T_w_c_corrected) keyframes_.at(id).T_w_c = T;
  for (const auto& [pid, p] : points_) update_point_appearance(pid);
}

SE3 Map::resolve_T_w_kf(KeyframeId id) const {
  const auto it = keyframes_.find(id);
  if (it != keyframes_.end()) return it->second.T_w_c;
  const auto c = culled_.find(id);
  require(c != culled_.end(), "Map::resolve_T_w_kf: unknown keyframe id " + std::to_string(id));
  return resolve_T_w_kf(c->second.first) * c->second.second;
}

}  // namespace s3m::slam
