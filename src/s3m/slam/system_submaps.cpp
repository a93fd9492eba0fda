// slam::System and sub-maps (map_merge.hpp): when relocalisation keeps failing a new sub-map starts
// (tracking side); merges found by the loop closer are remembered so requests still in flight
// follow them, and corrections are handed on in the world's terms (mapping side).
#include "s3m/slam/system.hpp"

#include <map>

namespace s3m::slam {

bool System::makes_submaps() const {
  const LoopClosingConfig& lc = config_.loop_closing;
  return closer_ && lc.enabled && lc.relocalisation && lc.loop.merge.enabled && !localize_only_;
}

// Step 3 of track() for a LOST frame. A session continuing in a loaded map that has tracked
// nothing yet, or whose map was tracked no further than its first frame (the camera was somewhere
// else when the recording started, or the next frames came too far apart), gives up after
// merge.start_frames failed relocalisations; a session that lost tracking after merge.lost_frames
// (frames too poor to relocalise do not count). This frame then starts the new sub-map (as its
// first keyframe, when it has enough depth; otherwise the next frame with enough does).
void System::recover(const RgbdFrame& frame, TrackerOutput& out, TrackResult& r) {
  if (relocalise(*out.features, frame.index, r)) {
    n_failed_relocalisations_ = 0;
    return;
  }
  // A frame with fewer keypoints than a relocalisation needs inliers (covered, dark, blank) cannot
  // tell where the camera is: no evidence that it left the map, so it does not bring a new sub-map
  // nearer. Counted, a blackout of a second started one, and the first frame after it, which
  // would have relocalised, became that sub-map's first keyframe instead.
  if (out.features->size() < config_.loop_closing.reloc.min_final_inliers) return;
  ++n_failed_relocalisations_;
  if (!makes_submaps()) return;
  const bool at_start = r.anchor.keyframe == kNoKeyframe || frames_in_submap_ <= 1;
  const MergeConfig& m = config_.loop_closing.loop.merge;
  if (n_failed_relocalisations_ < (at_start ? m.start_frames : m.lost_frames)) return;
  n_failed_relocalisations_ = 0;
  frames_in_submap_ = 0;
  tracker_.start_new_map(next_submap_++);
  out = tracker_.retrack(frame, out.features, 0);
  take_tracking(out, r);
}

// Sub-maps that never merged leave their frames out of the trajectory. Where the first map is the
// small one (the camera looked elsewhere at the start, or tracking failed right after it), keeping
// it as the world would leave out most of the run; the map with the most tracked frames becomes the
// world instead (ties: the first). Labels only: every sub-map keeps its own frame.
void System::choose_world() {
  if (config_.loop_closing.loop.merge.world != "largest" || world_loaded_ || n_keyframes_outside_world() == 0)
    return;
  const std::map<int, int> frames = tracked_frames_per_submap();
  int best = 0, most = frames.count(0) ? frames.at(0) : 0;
  for (const auto& [submap, n] : frames)
    if (n > most) best = submap, most = n;
  if (best == 0) return;
  map_.swap_submaps(0, best);
  world_moved_ = true;
}

std::map<int, int> System::tracked_frames_per_submap() const {
  std::map<int, int> frames;
  for (const auto& rec : records_)
    if (rec.state != FrameState::kLost) ++frames[map_.submap_of(rec.anchor.keyframe)];
  return frames;
}

int System::n_frames_outside_world() const {
  int n = 0;
  for (const auto& [submap, frames] : tracked_frames_per_submap()) n += submap != 0 ? frames : 0;
  return n;
}

std::shared_ptr<const LocalMapSnapshot> System::snapshot(KeyframeId ref, int max_keyframes) const {
  LocalMapSnapshot s = make_snapshot(map_, ref, max_keyframes);
  s.merged_into = merged_into_;
  return std::make_shared<const LocalMapSnapshot>(std::move(s));
}

int System::follow_merges(int submap) const {
  for (auto it = merged_into_.find(submap); it != merged_into_.end(); it = merged_into_.find(submap))
    submap = it->second.first;
  return submap;
}

void System::follow_merges(KeyFrameRequest& request) const {
  for (auto it = merged_into_.find(request.submap); it != merged_into_.end();
       it = merged_into_.find(request.submap)) {
    request.T_w_c = it->second.second * request.T_w_c;
    request.submap = it->second.first;
  }
}

std::optional<LoopCorrection> System::note_correction(std::optional<LoopCorrection> c) {
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
