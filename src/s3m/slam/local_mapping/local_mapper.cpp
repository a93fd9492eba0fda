#include "s3m/slam/local_mapping/local_mapper.hpp"

#include <algorithm>
#include <limits>

#include "s3m/core/error.hpp"
#include "s3m/core/timing.hpp"
#include "s3m/slam/map/depth_points.hpp"

namespace s3m::slam {

void MapperConfig::validate() const {
  require(close_depth_m > 0, "mapper.close_depth_m must be > 0");
  require(min_new_points >= 0, "mapper.min_new_points must be >= 0");
  require(min_found_ratio >= 0 && min_found_ratio <= 1, "mapper.min_found_ratio must be in [0, 1]");
  require(redundant_ratio > 0 && redundant_ratio <= 1, "mapper.redundant_ratio must be in (0, 1]");
  require(snapshot_keyframes >= 1 && fuse_neighbours >= 0,
          "mapper: snapshot_keyframes >= 1, fuse_neighbours >= 0");
  ba.validate();
  dense_links.validate();
}

LocalMapper::LocalMapper(Map& map, const PinholeCamera& camera, const MapperConfig& config,
                         int link_queue_capacity)
    : map_(map), camera_(camera), config_(config) {
  config_.validate();
  if (config_.dense_links.enabled) linker_.emplace(camera, config_.dense_links, link_queue_capacity);
}

KeyframeId LocalMapper::process(const KeyFrameRequest& request) {
  Stopwatch sw;
  stats_ = {};
  // 1. Keyframe with tracking's matches; its dense link to the previous keyframe (from the
  //    tracked poses) is measured now or queued for the linker's thread; 2. new points from
  //    depth; 3. cull weak recent points; 4. fuse duplicates with the neighbours; 5. local BA;
  //    6. drop redundant keyframes.
  const KeyframeId kf = insert_keyframe(request);
  if (linker_ && !request.image.rgb.empty()) linker_->add(kf, request.image, map_);
  create_points(kf, request.first_of_map);
  cull_recent_points(kf);
  fuse_with_neighbours(kf);
  if (config_.local_ba && map_.n_keyframes() > 2)
    stats_.ba = local_bundle_adjustment(map_, kf, camera_, config_.ba);
  if (config_.cull_keyframes) cull_keyframes(kf);
  stats_.ms = sw.elapsed_ms();
  return kf;
}

KeyframeId LocalMapper::insert_keyframe(const KeyFrameRequest& r) {
  for (const auto& v : r.visibility) map_.count_visible(v.id, v.n_visible, v.n_found);
  KeyFrame k;
  k.frame_index = r.frame_index;
  k.t_s = r.t_s;
  k.T_w_c = r.T_w_c;
  k.features = r.features;
  k.points = r.points;
  k.submap = r.submap;
  for (PointId& pid : k.points)
    if (pid != kNoId && !map_.has_point(pid)) pid = kNoId;  // culled while the request was queued
  const KeyframeId id = map_.add_keyframe(std::move(k));
  for (PointId pid : map_.keyframe(id).points)
    if (pid != kNoId) map_.update_point_appearance(pid);
  map_.update_covisibility(id);
  return id;
}

void LocalMapper::create_points(KeyframeId id, bool first_of_map) {
  const KeyFrame& kf = map_.keyframe(id);
  const auto& F = *kf.features;
  const double depth_limit_m = first_of_map ? std::numeric_limits<double>::infinity() : config_.close_depth_m;
  const auto chosen = depth_point_keypoints(
      F, [&](int i) { return kf.points[i] == kNoId; }, depth_limit_m, config_.min_new_points);
  for (const auto& [z, i] : chosen) {
    const auto& kp = F.keypoints[i];
    const Vec3 p_w = kf.T_w_c * camera_.backproject(kp.pt.x, kp.pt.y, z);
    recent_points_.emplace_back(map_.add_point(p_w, id, i), id);
  }
  stats_.n_new_points = static_cast<int>(chosen.size());
}

void LocalMapper::cull_recent_points(KeyframeId current) {
  std::deque<std::pair<PointId, KeyframeId>> keep;
  for (const auto& [pid, created] : recent_points_) {
    if (!map_.has_point(pid)) continue;
    const MapPoint& p = map_.point(pid);
    const KeyframeId age = current - created;
    if (p.found_ratio() < config_.min_found_ratio || (age >= 2 && p.observations.size() < 2)) {
      map_.erase_point(pid);
      ++stats_.n_culled_points;
    } else if (age < 3) {
      keep.emplace_back(pid, created);
    }
  }
  recent_points_.swap(keep);
}

void LocalMapper::fuse_with_neighbours(KeyframeId id) {
  // Neighbours and their best neighbours (ORB-SLAM's second ring).
  std::vector<KeyframeId> targets = map_.keyframe(id).best_covisible(config_.fuse_neighbours);
  const std::size_t first = targets.size();
  for (std::size_t i = 0; i < first; ++i)
    for (KeyframeId nb2 : map_.keyframe(targets[i]).best_covisible(5))
      if (nb2 != id && std::find(targets.begin(), targets.end(), nb2) == targets.end())
        targets.push_back(nb2);
  auto valid_points = [&](KeyframeId k) {
    std::vector<PointId> v;
    for (PointId pid : map_.keyframe(k).points)
      if (pid != kNoId) v.push_back(pid);
    return v;
  };
  // 1. This keyframe's points into the neighbours, 2. the neighbours' points into this keyframe.
  const std::vector<PointId> own = valid_points(id);
  for (KeyframeId t : targets) stats_.n_fused += fuse_points(map_, t, own, camera_, config_.fusion);
  std::vector<PointId> theirs;
  for (KeyframeId t : targets) {
    auto v = valid_points(t);
    theirs.insert(theirs.end(), v.begin(), v.end());
  }
  std::sort(theirs.begin(), theirs.end());
  theirs.erase(std::unique(theirs.begin(), theirs.end()), theirs.end());
  stats_.n_fused += fuse_points(map_, id, theirs, camera_, config_.fusion);
  for (PointId pid : valid_points(id)) map_.update_point_appearance(pid);
  map_.update_covisibility(id);
  for (KeyframeId t : targets)
    if (map_.has_keyframe(t)) map_.update_covisibility(t);
}

void LocalMapper::cull_keyframes(KeyframeId id) {
  // A neighbour is redundant when most of its close points are seen by >= 3 other keyframes at
  // the same or a finer scale: it adds nothing to BA but cost.
  for (KeyframeId nb : map_.keyframe(id).best_covisible()) {
    const KeyFrame& k = map_.keyframe(nb);
    if (k.is_root()) continue;
    const auto& F = *k.features;
    int n_points = 0, n_redundant = 0;
    for (int i = 0; i < F.size(); ++i) {
      const PointId pid = k.points[i];
      if (pid == kNoId || !F.has_depth(i) || F.depth_m[i] > config_.close_depth_m) continue;
      ++n_points;
      const int level = F.keypoints[i].octave;
      int n_obs = 0;
      for (const auto& [other, idx] : map_.point(pid).observations) {
        if (other == nb) continue;
        if (map_.keyframe(other).features->keypoints[idx].octave <= level + 1 && ++n_obs >= 3) break;
      }
      if (n_obs >= 3) ++n_redundant;
    }
    if (n_points > 0 && n_redundant > config_.redundant_ratio * n_points) {
      map_.erase_keyframe(nb);
      ++stats_.n_culled_keyframes;
    }
  }
}

}  // namespace s3m::slam
