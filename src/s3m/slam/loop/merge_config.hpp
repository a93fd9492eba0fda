#pragma once
// Settings of sub-maps and their merging (map_merge.hpp), part of LoopConfig.
#include <string>

namespace s3m::slam {

// `loop_closing.merge:` of a preset. Sub-maps need loop closing and relocalisation.
struct MergeConfig {
  bool enabled = true;
  // Frames that must all fail to relocalise before a new sub-map starts: at the start of a session
  // that continues in a loaded map (nothing tracked yet) ...
  int start_frames = 5;
  // ... and after tracking was lost (at 30 Hz 1 s: a short occlusion relocalises in the old map).
  // A map tracked no further than its first frame is not worth that wait: start_frames applies.
  int lost_frames = 30;
  // Which map the session's poses are in at the end when sub-maps never merged: "first" (the map of
  // the first frame, or the loaded one) or "largest" (the one with the most tracked frames, ties to
  // the first; ORB-SLAM3 saves its trajectory in the map with the most keyframes). A session that
  // continues in a loaded map always keeps it.
  std::string world = "largest";
  // After a merge, one bundle adjustment over the whole map (ORB-SLAM3 runs one too): the points
  // both sides share pull the newcomer's keyframes near the seam onto the map, and both settle
  // together (see docs/DECISIONS.md, "Sub-map merges: global BA after a merge").
  bool global_ba = true;
  void validate() const;
};

}  // namespace s3m::slam
