#pragma once
// Local mapping: turns each keyframe request from tracking into map content. One visible process()
// with numbered steps; owns nothing but a reference to the Map (the caller, slam::System, decides
// which thread that is, and runs loop closing and makes tracking's snapshot after it).
#include <deque>
#include <optional>
#include <utility>

#include "s3m/core/camera.hpp"
#include "s3m/slam/map/local_map.hpp"
#include "s3m/slam/map/map.hpp"
#include "s3m/slam/map/point_fusion.hpp"
#include "s3m/slam/odometry/keyframe_links.hpp"
#include "s3m/slam/optim/bundle_adjustment.hpp"

namespace s3m::slam {

struct MapperConfig {
  double close_depth_m = 3.0;  // points are created for all keypoints closer than this [m] ...
  // ... and for at least this many of the closest ones. ORB-SLAM2 takes 100 (its far depth, as a
  // virtual stereo disparity, is weak); with depth weighted by its sensor model far points are
  // safe, and in views beyond close_depth_m 100 new points per keyframe are too few to keep
  // tracking through fast turns (see docs/DECISIONS.md, "Keyframe policy").
  int min_new_points = 300;
  double min_found_ratio = 0.25;  // recent points found less often than this are culled
  int fuse_neighbours = 10;       // covisible keyframes searched for duplicates
  bool local_ba = true;
  bool cull_keyframes = true;
  double redundant_ratio = 0.9;  // a keyframe whose points are this often seen by >= 3 others goes
  int snapshot_keyframes = 40;   // keyframes in the snapshot sent to tracking
  // System::finish() runs one BA over the whole map (not in localisation-only sessions), holding
  // keyframes it would move too far (ba.max_keyframe_step_*). On by default: with depth weighted by
  // its sensor model it makes most simulator flights better, those that revisit most, and leaves
  // the kitchen about where it was (see docs/DECISIONS.md, "Final global BA").
  bool final_global_ba = true;
  // Dense RGB-D links between consecutive keyframes, constraints of the final global BA.
  DenseLinkConfig dense_links;
  BaConfig ba;
  FusionConfig fusion;
  void validate() const;
};

struct MapperStats {
  int n_new_points = 0, n_fused = 0, n_culled_points = 0, n_culled_keyframes = 0;
  LocalBaStats ba;
  double ms = 0;
};

class LocalMapper {
 public:
  // link_queue_capacity > 0: the dense keyframe links are measured on a thread of their own
  // (KeyframeLinker), with at most that many keyframes waiting; 0: inside process().
  LocalMapper(Map& map, const PinholeCamera& camera, const MapperConfig& config, int link_queue_capacity = 0);
  // Returns the new keyframe's id (make_snapshot(map, id, ...) is what tracking continues with).
  KeyframeId process(const KeyFrameRequest& request);
  const MapperStats& last_stats() const { return stats_; }
  // Waits for the dense keyframe links still being measured (rethrows the linker's error).
  void finish_links() {
    if (linker_) linker_->finish();
  }
  // The dense keyframe links measured so far when the run's links are trusted, else none; and
  // their summary (empty when dense_links is off). Complete after finish_links().
  std::vector<KeyframeLink> links() const {
    return linker_ ? linker_->trusted_links() : std::vector<KeyframeLink>{};
  }
  KeyframeLinkSummary link_summary() const { return linker_ ? linker_->summary() : KeyframeLinkSummary{}; }

 private:
  KeyframeId insert_keyframe(const KeyFrameRequest& r);
  void create_points(KeyframeId kf, bool first_of_map);
  void cull_recent_points(KeyframeId kf);
  void fuse_with_neighbours(KeyframeId kf);
  void cull_keyframes(KeyframeId kf);

  Map& map_;
  PinholeCamera camera_;
  MapperConfig config_;
  std::optional<KeyframeLinker> linker_;
  std::deque<std::pair<PointId, KeyframeId>> recent_points_;  // (point, keyframe that created it)
  MapperStats stats_;
};

}  // namespace s3m::slam
