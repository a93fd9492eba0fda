// The tracking side when tracking is lost or the map is frozen: relocalisation against the map,
// new sub-maps when it keeps failing (loop/map_merge.hpp), and localisation only.
#include "s3m/slam/tracking_front_end.hpp"

#include "s3m/core/error.hpp"

namespace s3m::slam {

bool TrackingFrontEnd::makes_submaps() const {
  const LoopClosingConfig& lc = config_.loop_closing;
  return back_.has_place_recognition() && lc.enabled && lc.relocalisation && lc.loop.merge.enabled &&
         !localize_only_;
}

void TrackingFrontEnd::continue_map(KeyframeId next_keyframe_id, bool localize_only) {
  require(before_first_frame(), "System::load_map: only before the first frame");
  tracker_.continue_map(next_keyframe_id);
  tracker_.set_localize_only(localize_only);
  localize_only_ = localize_only;
}

// Step 3 of track() for a LOST frame. A session continuing in a loaded map that has tracked
// nothing yet, or whose map was tracked no further than its first frame (the camera was somewhere
// else when the recording started, or the next frames came too far apart), gives up after
// merge.start_frames failed relocalisations; a session that lost tracking after merge.lost_frames
// (frames too poor to relocalise do not count). This frame then starts the new sub-map (as its
// first keyframe, when it has enough depth; otherwise the next frame with enough does).
void TrackingFrontEnd::recover(const RgbdFrame& frame, TrackerOutput& out, TrackResult& r) {
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

// Relocalises a LOST frame against every keyframe. The map and the BoW index belong to the
// mapping stage: the search runs as a map query and copies out what tracking needs. On success
// tracking resumes from the found pose with the local map around the matched keyframe.
bool TrackingFrontEnd::relocalise(const features::FrameFeatures& f, int frame_index, TrackResult& r) {
  RelocAnswer a;
  const int submap = makes_submaps() ? tracker_.submap() : -1;  // only where tracking was
  query_map([&](const Map&) { a = back_.relocalise(f, submap); });
  if (!a.result.success) return false;
  // In a loaded map before the first relocalisation there is no reference keyframe yet, and in
  // localisation only no keyframe will be made: the matched keyframe becomes the reference.
  if (r.anchor.keyframe == kNoKeyframe || localize_only_)
    tracker_.set_local_map(std::move(a.snapshot), frame_index);
  else
    tracker_.set_snapshot(std::move(a.snapshot));
  tracker_.set_pose(a.result.T_w_c);
  r.state = FrameState::kRelocalised;
  r.T_w_c = a.result.T_w_c;
  r.T_w_r = robot_pose(a.result.T_w_c, config_.T_c_r);
  r.n_inliers = a.result.n_inliers;
  r.anchor = {a.result.keyframe, a.T_w_kf.inverse() * a.result.T_w_c};
  return true;
}

// Localisation only: where tracking would have made a keyframe, it continues with the local map
// around the loaded keyframe that sees most of what it tracks (ORB-SLAM's localisation mode).
void TrackingFrontEnd::move_local_map(const std::vector<PointId>& tracked_points, int frame_index) {
  std::shared_ptr<const LocalMapSnapshot> snapshot;
  query_map([&](const Map& map) {
    const KeyframeId best = best_covisible_keyframe(map, tracked_points);
    if (best != kNoKeyframe) snapshot = back_.snapshot(best, config_.mapper.snapshot_keyframes);
  });
  if (snapshot) tracker_.set_local_map(std::move(snapshot), frame_index);
}

}  // namespace s3m::slam
