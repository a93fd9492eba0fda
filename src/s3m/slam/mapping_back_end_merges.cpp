// The mapping side and sub-maps (loop/map_merge.hpp): merges found by the loop closer are
// remembered, so that requests still in flight and tracking's snapshots follow them, and
// corrections are handed on in the world's terms.
#include <map>

#include "s3m/slam/mapping_back_end.hpp"

namespace s3m::slam {

std::shared_ptr<const LocalMapSnapshot> MappingBackEnd::snapshot(KeyframeId ref, int max_keyframes) const {
  LocalMapSnapshot s = make_snapshot(map_, ref, max_keyframes);
  s.merged_into = merged_into_;
  return std::make_shared<const LocalMapSnapshot>(std::move(s));
}

int MappingBackEnd::follow_merges(int submap) const {
  for (auto it = merged_into_.find(submap); it != merged_into_.end(); it = merged_into_.find(submap))
    submap = it->second.first;
  return submap;
}

void MappingBackEnd::follow_merges(KeyFrameRequest& request) const {
  for (auto it = merged_into_.find(request.submap); it != merged_into_.end();
       it = merged_into_.find(request.submap)) {
    request.T_w_c = it->second.second * request.T_w_c;
    request.submap = it->second.first;
  }
}

std::optional<LoopCorrection> MappingBackEnd::note_correction(std::optional<LoopCorrection> c) {
  if (!c) return c;
  if (c->is_merge()) {
    merged_into_[c->merged_from] = {c->merged_into, c->T_into_from};
    ++n_merges_;
  }
  if (map_.submap_of(c->current_kf) != 0) return std::nullopt;  // the world did not change
  auto world_only = [&](std::map<KeyframeId, SE3>& poses) {
    for (auto it = poses.begin(); it != poses.end();)
      it = map_.submap_of(it->first) == 0 ? std::next(it) : poses.erase(it);
  };
  world_only(c->T_w_kf_before);
  world_only(c->T_w_kf_after);
  // A merge into the world: culled keyframes of the joined sub-map get their pose too (the pipeline
  // anchored clouds to some of them while they were outside the world).
  if (c->is_merge() && c->merged_into == 0) c->T_w_kf_after.merge(map_.culled_poses_in(0));
  return c;
}

}  // namespace s3m::slam
