#pragma once
// Loop closing (ORB-SLAM's LoopClosing, SE3 for RGB-D). slam::System runs it in the mapping stage
// after each keyframe's local mapping, so it owns the Map while it works; process() steps:
//   1 index the keyframe's BoW, 2 covisibility-consistent candidates, 3 geometric verification
//   (BoW matches -> 3D-3D RANSAC -> guided search -> refinement), 4 pose propagation to the
//   keyframe's neighbourhood and fusion of duplicated map points, 5 essential-graph optimisation,
//   6 optional global BA; the correction is returned (System hands it to tracking's caller).
#include <map>
#include <memory>
#include <optional>
#include <set>
#include <string>
#include <utility>
#include <vector>

#include "s3m/core/camera.hpp"
#include "s3m/features/bow_matcher.hpp"
#include "s3m/slam/loop/loop_detector.hpp"
#include "s3m/slam/loop/loop_geometry.hpp"
#include "s3m/slam/loop/loop_keyframe_index.hpp"
#include "s3m/slam/loop/merge_config.hpp"
#include "s3m/slam/map/map.hpp"
#include "s3m/slam/odometry/keyframe_links.hpp"
#include "s3m/slam/optim/bundle_adjustment.hpp"
#include "s3m/slam/optim/pose_graph.hpp"

namespace s3m::slam {

struct LoopConfig {
  int min_keyframes = 10;             // no loop search in a map smaller than this
  int min_keyframes_since_loop = 10;  // keyframes between two loop closures
  int direct_level = 2;               // vocabulary level of the direct index for BoW matching
  LoopDetectorConfig detector;
  features::BowMatchConfig bow_match;
  int min_bow_matches = 20;           // candidate needs this many BoW matches with map points
  Se3RansacConfig ransac;             // 3D-3D verification (min_inliers = 20)
  int loop_group_size = 10;           // covisible keyframes of the loop keyframe searched by projection
  double search_radius_factor = 3.0;  // projection search window = factor * level scale [px]
  int min_projection_matches = 40;    // matches with the loop group after the guided search
  int essential_min_weight = 100;     // covisibility edges in the essential graph
  PoseGraphConfig pose_graph;
  bool global_ba = false;  // full BA after the pose graph (slow on large maps)
  BaConfig ba;
  MergeConfig merge;  // sub-maps and their merging (map_merge.hpp)
  void validate() const;
};

// What a loop closure changed; whoever built something from keyframe poses re-integrates it.
struct LoopCorrection {
  KeyframeId current_kf = kNoId;
  KeyframeId loop_kf = kNoId;
  SE3 T_loop_current = SE3::Identity();     // verified relative pose (current camera -> loop camera)
  int n_matches = 0;                        // current keypoints matched to loop-group points
  int n_fused = 0;                          // duplicated points merged or re-observed
  std::map<KeyframeId, SE3> T_w_kf_before;  // every keyframe, before the correction
  std::map<KeyframeId, SE3> T_w_kf_after;   // every keyframe, after pose graph (and global BA)
  // A merge of two sub-maps (map_merge.cpp) rather than a loop: sub-map merged_from moved into
  // merged_into's frame by T_into_from before fusion and optimisation (T_w_kf_before holds its
  // keyframes in their old frame). -1: a loop closure.
  int merged_from = -1, merged_into = -1;
  SE3 T_into_from = SE3::Identity();
  bool is_merge() const { return merged_from >= 0; }
};

// What geometric verification tried (the offline merge reports it when nothing overlaps).
struct VerifyStats {
  int candidates = 0;    // candidate keyframes verified
  int bow_matched = 0;   // ... with enough BoW matches and a 3D-3D RANSAC pose
  int best_matches = 0;  // most projection matches any candidate reached
};

class LoopCloser {
 public:
  LoopCloser(std::shared_ptr<const features::Vocabulary> vocabulary, const PinholeCamera& camera,
             const LoopConfig& config = {});

  // Processes a new keyframe; returns what changed when a loop was closed or two sub-maps merged.
  std::optional<LoopCorrection> process(Map& map, KeyframeId kf);
  // Merging (map_merge.cpp): verifies candidates in other sub-maps than kf's and, when one holds,
  // merges the two sub-maps (the younger moves into the older one's frame: SE3 from 3D-3D matches,
  // point fusion, welding BA at the seam, essential graph over both). process() calls it with the
  // detector's candidates; the offline merge of two saved maps with BoW candidates directly.
  std::optional<LoopCorrection> merge_at(Map& map, KeyframeId kf, const std::vector<KeyframeId>& candidates,
                                         VerifyStats* stats = nullptr);
  // Geometric verification alone, the map unchanged: the first candidate that holds, keyframe kf's
  // pose in that candidate's frame and the projection matches that support it.
  struct Recognition {
    KeyframeId loop_kf = kNoId;
    SE3 T_w_cur = SE3::Identity();
    int n_matches = 0;
  };
  std::optional<Recognition> recognise(const Map& map, KeyframeId kf,
                                       const std::vector<KeyframeId>& candidates,
                                       VerifyStats* stats = nullptr) const;
  // The BoW index of all keyframes seen so far (relocalisation searches it too).
  const KeyFrameBowIndex& index() const { return index_; }
  KeyFrameBowIndex& index() { return index_; }
  const std::vector<std::pair<KeyframeId, KeyframeId>>& loop_edges() const { return loop_edges_; }
  // A loaded map's loop edges (its index goes in through index()), before the first process().
  void restore_loop_edges(std::vector<std::pair<KeyframeId, KeyframeId>> edges) {
    loop_edges_ = std::move(edges);
  }

 private:
  struct Verified {
    KeyframeId loop_kf = kNoId;
    SE3 T_w_cur = SE3::Identity();                 // corrected pose of the current keyframe
    std::vector<std::pair<int, PointId>> matches;  // current keypoint -> loop-group point
  };
  std::optional<Verified> verify(const Map& map, KeyframeId cur, const std::vector<KeyframeId>& candidates,
                                 VerifyStats* stats = nullptr) const;
  std::optional<SE3> ransac_with_bow(const Map& map, KeyframeId cur, KeyframeId cand) const;
  std::vector<std::pair<int, PointId>> search_loop_group(const Map& map, KeyframeId cur, KeyframeId loop_kf,
                                                         const SE3& T_w_cur) const;
  LoopCorrection correct(Map& map, KeyframeId cur, const Verified& v);
  LoopCorrection merge(Map& map, KeyframeId cur, const Verified& v);
  // Steps shared by loops and merges once the current side sits on the loop side: fuse duplicated
  // points, link the two sides, optimise the essential graph of cur's sub-map (T_before: the
  // shape to keep; fixed: keyframes held, besides the sub-map's oldest).
  void weld(Map& map, KeyframeId cur, const Verified& v, const std::set<KeyframeId>& group,
            const std::map<KeyframeId, std::set<KeyframeId>>& neighbours_before,
            const std::map<KeyframeId, SE3>& T_before, const std::set<KeyframeId>& fixed,
            LoopCorrection& out);

  PinholeCamera camera_;
  LoopConfig config_;
  KeyFrameBowIndex index_;
  LoopDetector detector_;
  std::vector<std::pair<KeyframeId, KeyframeId>> loop_edges_;  // (current, loop) of every closed loop
  KeyframeId last_loop_kf_ = kNoId;
};

}  // namespace s3m::slam
