#include "s3m/pipeline/keyframe_store.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>

#include "s3m/core/error.hpp"
#include "s3m/pipeline/cloud_from_frame.hpp"

namespace s3m::pipeline {

void KeyframeStore::note_keyframe(KeyframeId id, const SE3& T_w_kf, bool detached) {
  keyframes_.insert_or_assign(id, T_w_kf);
  if (detached)
    detached_.insert(id);
  else
    detached_.erase(id);
}

void KeyframeStore::add(KeyframeId keyframe, const SE3& T_w_c, int frame_index, mapping::LabeledCloud cloud) {
  const auto it = keyframes_.find(keyframe);
  require(it != keyframes_.end(), "KeyframeStore::add: keyframe " + std::to_string(keyframe) + " was not noted");
  add_kept({{keyframe, it->second.inverse() * T_w_c}, frame_index, std::move(cloud), session_});
}

int KeyframeStore::next_session() const {
  int last = session_;
  for (const KeptCloud& c : clouds_) last = std::max(last, c.session);
  return last + 1;
}

std::set<int> KeyframeStore::sessions_in_world() const {
  std::set<int> sessions;
  for (const KeptCloud& c : clouds_)
    if (in_world(c)) sessions.insert(c.session);
  return sessions;
}

void KeyframeStore::add_kept(KeptCloud kept) {
  require(keyframes_.count(kept.anchor.keyframe),
          "KeyframeStore::add_kept: keyframe " + std::to_string(kept.anchor.keyframe) + " was not noted");
  kept.cloud.shrink_to_fit();  // kept for the whole run: hold no spare capacity from building it
  clouds_.push_back(std::move(kept));
  bytes_ += cloud_bytes(clouds_.back().cloud) + sizeof(KeptCloud);
  while (budget_bytes_ > 0 && bytes_ > budget_bytes_ && clouds_.size() > 1) drop_most_redundant();
}

namespace {

// Viewpoint cell of a camera pose: position in 0.5 m cells, optical axis (camera z) in cells of
// 0.5 per unit-vector component (~30 deg). Poses in one cell see nearly the same surfaces.
std::array<int, 6> viewpoint_cell(const SE3& T_w_c) {
  const Vec3 p = T_w_c.translation() / 0.5, d = T_w_c.linear().col(2) / 0.5;
  return {int(std::floor(p.x())), int(std::floor(p.y())), int(std::floor(p.z())),
          int(std::lround(d.x())), int(std::lround(d.y())), int(std::lround(d.z()))};
}

bool is_keyframe_cloud(const KeptCloud& c) {
  return c.anchor.T_kf_c.translation().norm() < 1e-9 && c.anchor.T_kf_c.linear().isIdentity(1e-9);
}

}  // namespace

void KeyframeStore::drop_most_redundant() {
  // Cells by current pose (corrections move clouds between cells); the newest cloud is exempt.
  std::map<std::array<int, 6>, std::vector<std::size_t>> cells;
  for (std::size_t i = 0; i + 1 < clouds_.size(); ++i) cells[viewpoint_cell(T_w_c(clouds_[i]))].push_back(i);
  const auto crowded = std::max_element(cells.begin(), cells.end(), [](const auto& a, const auto& b) {
    return a.second.size() < b.second.size();  // first (lowest cell) among equals: deterministic
  });
  const std::vector<std::size_t>& in_cell = crowded->second;
  const auto rider = std::find_if(in_cell.begin(), in_cell.end(),
                                  [&](std::size_t i) { return !is_keyframe_cloud(clouds_[i]); });
  const std::size_t victim = rider != in_cell.end() ? *rider : in_cell.front();  // oldest first
  bytes_ -= cloud_bytes(clouds_[victim].cloud) + sizeof(KeptCloud);
  clouds_.erase(clouds_.begin() + static_cast<std::ptrdiff_t>(victim));
  ++dropped_;
}

double KeyframeStore::update_poses(const std::map<KeyframeId, SE3>& T_w_kf) {
  if (T_w_kf.empty()) return 0.0;
  double max_shift_m = 0.0;
  // Detached keyframes a correction lists have joined the world (their T_w_kf was in a sub-map's
  // frame: no shift to measure, the clouds anchored to them enter the map now).
  for (auto it = detached_.begin(); it != detached_.end();)
    if (T_w_kf.count(*it)) {
      const KeyframeId id = *it;
      it = detached_.erase(it);
      if (std::any_of(clouds_.begin(), clouds_.end(), [&](const KeptCloud& c) { return c.anchor.keyframe == id; }))
        max_shift_m = std::numeric_limits<double>::infinity();
    } else {
      ++it;
    }
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

void KeyframeStore::set_world(const std::map<KeyframeId, SE3>& T_w_kf) {
  for (const auto& [id, T] : T_w_kf) keyframes_.insert_or_assign(id, T);
  detached_.clear();
  for (const auto& [id, T] : keyframes_)
    if (!T_w_kf.count(id)) detached_.insert(id);
}

}  // namespace s3m::pipeline
