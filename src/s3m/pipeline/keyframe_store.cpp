#include "s3m/pipeline/keyframe_store.hpp"

#include <algorithm>

#include "s3m/core/error.hpp"

namespace s3m::pipeline {

void KeyframeStore::add(KeyframeId anchor, const SE3& T_w_c, int frame_index, mapping::LabeledCloud cloud) {
  const auto it = keyframes_.find(anchor);
  require(it != keyframes_.end(), "KeyframeStore::add: keyframe " + std::to_string(anchor) + " was not noted");
  clouds_.push_back({anchor, it->second.inverse() * T_w_c, frame_index, std::move(cloud)});
}

double KeyframeStore::update_poses(const std::map<KeyframeId, SE3>& T_w_kf) {
  if (T_w_kf.empty()) return 0.0;
  double max_shift_m = 0.0;
  std::map<KeyframeId, SE3> updated;
  for (const auto& [id, T_old] : keyframes_) {
    SE3 T_new = T_old;
    if (auto it = T_w_kf.find(id); it != T_w_kf.end()) {
      T_new = it->second;
    } else {
      // A keyframe SLAM no longer has: apply the rigid correction of the nearest listed keyframe
      // (by id, i.e. by creation time) that we also know the old pose of.
      auto hi = T_w_kf.lower_bound(id);
      auto lo = hi == T_w_kf.begin() ? hi : std::prev(hi);
      auto near = (hi == T_w_kf.end() || (id - lo->first) <= (hi->first - id)) ? lo : hi;
      if (auto old = keyframes_.find(near->first); old != keyframes_.end())
        T_new = near->second * old->second.inverse() * T_old;
    }
    max_shift_m = std::max(max_shift_m, (T_new.translation() - T_old.translation()).norm());
    updated.emplace(id, T_new);
  }
  for (const auto& [id, T] : T_w_kf) updated.try_emplace(id, T);  // keyframes not noted yet
  keyframes_ = std::move(updated);
  return max_shift_m;
}

std::size_t KeyframeStore::bytes() const {
  std::size_t b = 0;
  for (const auto& c : clouds_) b += cloud_bytes(c.cloud) + sizeof(KeptCloud);
  return b;
}

}  // namespace s3m::pipeline
