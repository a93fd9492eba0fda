#pragma once
// Sub-maps and their merging (ORB-SLAM3's Atlas for RGB-D). A session that cannot
// relocalise does not stay LOST: after a few failed frames it starts a new sub-map in a frame of
// its own (System::track, step 3). Place recognition (the BoW keyframe index, the loop detector's
// candidates and geometric verification) later finds an older sub-map from one of its keyframes;
// then the two are merged (LoopCloser::merge_at):
//   1 SE3 from 3D-3D matches with depth (RGB-D measures metric depth, so the scale is known: a
//     Sim3 would only add a degree of freedom to get wrong); the younger sub-map moves rigidly
//     into the older one's frame and its spanning tree is hung below the matched keyframe,
//   2 duplicated points fused across the seam (both ways), 3 a welding BA of the moved side's
//     keyframes at the seam on the shared points, 4 essential-graph optimisation over both sides
//     (seam links as loop edges) with the older sub-map and the welded window held: the older map
//     (a loaded session, usually the better converged) is not bent by the newcomer (ORB-SLAM3's
//     merge does the same).
// Sub-map 0 is the world (the session's first map, or the loaded one): poses are reported in it,
// and what never joins it is neither reported nor saved.
//
// merge_sessions() does the same offline for two saved maps (`s3m merge RUN_A RUN_B`);
// find_session_overlap() only measures how well they overlap.
#include <memory>
#include <set>
#include <string>

#include "s3m/slam/io/map_io.hpp"
#include "s3m/slam/loop/loop_closer.hpp"

namespace s3m::slam {

// The offline merge's search: which keyframe pairs are verified and which alignment is accepted.
struct SessionMergeConfig {
  int candidates_per_keyframe = 3;  // run A keyframes tried per run B keyframe, best BoW score first
  // The alignment of the best-verified pair is accepted when at least this many verified pairs
  // (counting itself) agree with it, as the loop detector asks consecutive keyframes to agree.
  int min_agreeing = 2;
  double agree_m = 0.10, agree_deg = 3.0;
  void validate() const;
};

struct MergedSessions {
  Map map;  // A's keyframes keep their ids; B's are shifted by b_offset
  KeyFrameBowIndex index;
  LoopEdges loop_edges;
  KeyframeId b_offset = 0;
  SE3 T_a_b = SE3::Identity();  // B's world in A's, as verified (before fusion and the pose graph)
  KeyframeId a_keyframe = kNoId, b_keyframe = kNoId;  // the pair the merge was made at (merged ids)
  int n_matches = 0, n_agreeing = 0, n_verified = 0;
  LoopCorrection correction;  // every keyframe's pose before and after
};

// How well saved map b is recognised in saved map a (steps 1-3 of merge_sessions, nothing merged):
// an N-way merge orders its merges by it.
struct SessionOverlap {
  bool placed = false;  // an alignment at least config.min_agreeing verified pairs agree on
  int n_verified = 0;   // b's keyframes verified against one of a's
  int n_agreeing = 0;   // of those, agreeing with the best pair's alignment (0 when not placed)
  int n_matches = 0;    // the best pair's projection matches
};
SessionOverlap find_session_overlap(LoadedSlamMap a, const LoadedSlamMap& b,
                                    std::shared_ptr<const features::Vocabulary> vocabulary,
                                    const LoopConfig& loop, const SessionMergeConfig& config = {});

// Merges saved map b into saved map a (same camera and vocabulary: load both with a's camera).
// Throws s3m::Error when no keyframe of b is recognised in a, saying what was tried.
MergedSessions merge_sessions(LoadedSlamMap a, const LoadedSlamMap& b,
                              std::shared_ptr<const features::Vocabulary> vocabulary, const LoopConfig& loop,
                              const SessionMergeConfig& config = {});

}  // namespace s3m::slam
