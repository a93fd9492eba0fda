#pragma once
// Relocalisation of a LOST frame against the whole map (ORB-SLAM's Relocalization):
//   1 BoW of the frame, 2 keyframe candidates from the database (best scores first), 3 BoW
//   matches with each candidate's map points, 4 PnP RANSAC + pose-only optimisation with the
//   RGB-D residual, 5 guided search for the candidate's local map (wide, then narrow window)
//   with re-optimisation after each pass.
#include <memory>
#include <optional>

#include "s3m/core/camera.hpp"
#include "s3m/features/bow_matcher.hpp"
#include "s3m/features/frame_features.hpp"
#include "s3m/slam/loop/loop_keyframe_index.hpp"
#include "s3m/slam/map/map.hpp"
#include "s3m/slam/tracking/reloc_pnp.hpp"

namespace s3m::slam {

struct RelocConfig {
  int max_candidates = 5;         // keyframes tried, best BoW score first
  double min_score_ratio = 0.75;  // candidates must score at least this fraction of the best
  features::BowMatchConfig bow_match;
  int min_bow_matches = 15;           // ORB-SLAM: 15
  PnpConfig pnp;                      // min_inliers after RANSAC
  int local_keyframes = 20;           // candidate's covisible keyframes searched by projection
  double wide_radius_factor = 10.0;   // first projection search around the RANSAC pose [px per level scale]
  double search_radius_factor = 3.0;  // second search around the refined pose [px per level scale]
  // ORB-SLAM asks 50 after refinement for any sensor; with metric depth in the map points a pose
  // that 30 projection inliers agree on (after two guided passes) is already unambiguous.
  int min_final_inliers = 30;
  int snapshot_keyframes = 40;  // local map handed to tracking around the relocalised keyframe
  void validate() const;
};

struct RelocResult {
  bool success = false;
  SE3 T_w_c = SE3::Identity();
  KeyframeId keyframe = kNoId;  // candidate the frame was relocalised against
  int n_inliers = 0;
  int n_candidates = 0;  // keyframes tried
};

// Relocalises frame features f against the map, using the keyframe BoW index (kept in sync
// with the map by the loop closer or by the caller through index.sync(map)). submap >= 0: only
// against that sub-map's keyframes (the one tracking was in; a pose in another sub-map's frame
// would be in the wrong world).
RelocResult relocalise(const features::FrameFeatures& f, const Map& map, const KeyFrameBowIndex& index,
                       const PinholeCamera& camera, const RelocConfig& config = {}, int submap = -1);

}  // namespace s3m::slam
