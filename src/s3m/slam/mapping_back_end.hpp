#pragma once
// The mapping side of slam::System: the Map and everything that changes it (local mapping, loop
// closing and sub-map merges, the final bundle adjustment). In threaded mode only the mapping
// thread touches it, through serve(); in single-thread mode tracking calls it inline. Tracking
// sees the map only through the LocalMapSnapshot copies and LoopCorrections it hands back.
#include <functional>
#include <future>
#include <map>
#include <memory>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "s3m/core/bounded_queue.hpp"
#include "s3m/core/camera.hpp"
#include "s3m/slam/local_mapping/local_mapper.hpp"
#include "s3m/slam/loop/loop_closer.hpp"
#include "s3m/slam/map/map.hpp"
#include "s3m/slam/slam_config.hpp"
#include "s3m/slam/tracking/reloc.hpp"

namespace s3m::slam {

// A read of the whole map for the tracking side. Runs where the Map may be touched: inline in
// single-thread mode, on the mapping thread in threaded mode.
using MapQuery = std::function<void(const Map&)>;
// Read-only look at the map after each keyframe's mapping stage (tests pace local mapping with
// it); runs on the mapping thread in threaded mode.
using MappingObserver = std::function<void(const Map&, KeyframeId)>;

// What the mapping thread receives: a keyframe to map, or a map query to answer.
struct MapperJob {
  std::optional<KeyFrameRequest> keyframe;
  MapQuery query;
  std::shared_ptr<std::promise<void>> done;  // set once the query ran (value or its exception)
};

// What the mapping stage gives back for one keyframe.
struct MappedKeyframe {
  std::shared_ptr<const LocalMapSnapshot> snapshot;
  std::optional<LoopCorrection> correction;
};

// A relocalisation's answer, copied out of the map for the tracking side.
struct RelocAnswer {
  RelocResult result;
  std::shared_ptr<const LocalMapSnapshot> snapshot;  // around the matched keyframe
  SE3 T_w_kf = SE3::Identity();                      // the matched keyframe's pose
};

class MappingBackEnd {
 public:
  // vocabulary: place recognition (config.loop_closing: loops, relocalisation); null = neither.
  // link_queue_capacity: > 0 measures the dense keyframe links on a thread of their own.
  MappingBackEnd(const PinholeCamera& camera, const SlamConfig& config,
                 std::shared_ptr<const features::Vocabulary> vocabulary, MappingObserver observer,
                 int link_queue_capacity);

  // The mapping stage for one keyframe: local mapping, loop closing, the snapshot for tracking.
  MappedKeyframe map_keyframe(KeyFrameRequest request);
  // The mapping thread's loop: answers jobs until `jobs` is closed (or `mapped` is).
  void serve(BoundedQueue<MapperJob>& jobs, BoundedQueue<MappedKeyframe>& mapped);
  // After the last keyframe: the dense links finish, then (final_ba) one bundle adjustment over
  // the whole map.
  void finish(bool final_ba);

  // The local map around ref, with the merges made so far (what tracking follows).
  std::shared_ptr<const LocalMapSnapshot> snapshot(KeyframeId ref, int max_keyframes) const;
  // Where sub-map `submap` lives now after the merges made so far.
  int follow_merges(int submap) const;
  // Relocalises f against the keyframes of `submap` (-1: every sub-map).
  RelocAnswer relocalise(const features::FrameFeatures& f, int submap) const;

  // Continue in a saved map (before any keyframe); next_keyframe_id for the tracker.
  KeyframeId load(const std::string& path);
  void save(const std::string& path) const;  // the world only (sub-map 0)

  bool has_place_recognition() const { return closer_.has_value(); }
  bool closes_loops() const { return closer_ && config_.loop_closing.enabled; }
  bool relocalises() const { return closer_ && config_.loop_closing.relocalisation; }
  int n_loops() const { return closer_ ? int(closer_->loop_edges().size()) : 0; }
  int n_merges() const { return n_merges_; }
  int n_global_ba_outliers() const { return n_global_ba_outliers_; }
  KeyframeLinkSummary link_summary() const { return mapper_.link_summary(); }
  const Map& map() const { return map_; }
  Map& map() { return map_; }

 private:
  void follow_merges(KeyFrameRequest& request) const;
  // A merge is remembered (requests in flight follow it); a correction is handed on for the
  // world's keyframes only (none: a loop inside another sub-map).
  std::optional<LoopCorrection> note_correction(std::optional<LoopCorrection> c);

  PinholeCamera camera_;
  SlamConfig config_;
  Map map_;
  LocalMapper mapper_;
  std::optional<LoopCloser> closer_;  // place recognition (loop closing and/or relocalisation)
  std::shared_ptr<const features::Vocabulary> vocabulary_;
  MappingObserver observer_;
  // Merged sub-map -> (the sub-map it joined, T_into_from).
  std::map<int, std::pair<int, SE3>> merged_into_;
  int n_merges_ = 0;
  int n_global_ba_outliers_ = 0;
};

}  // namespace s3m::slam
