#pragma once
// s3m::slam::System — the one entry point for RGB-D SLAM: tracking, local mapping, loop closing
// and relocalisation behind track(). Single-thread mode runs the mapping stage (local mapping,
// then loop closing) inside track() right after a keyframe and is deterministic; threaded mode
// runs it in its own thread, connected to tracking by two bounded queues (requests one way,
// mapped keyframes the other), and with slam.mapping_lag_frames >= 1 (the default 1) it is
// deterministic too (1: the single-thread trajectory). Tracking never touches the Map; the
// mapping stage owns it. The dense keyframe links (slam.mapper.dense_links) are measured on a
// third thread in threaded mode (KeyframeLinker), with the same results.
//
//   auto vocab = std::make_shared<const features::Vocabulary>(features::Vocabulary::load(path));
//   slam::System slam(camera, slam::load_slam_config("config/slam_default.yaml"), vocab);
//   for (const RgbdFrame& f : frames) {
//     auto r = slam.track(f);  // r.T_w_c, r.state; r.corrections: loops closed since the last frame
//   }
//   slam.finish();
//   const auto frames = slam.camera_trajectory();  // FramePose: a StampedPose + frame index, state
//   io::write_tum_trajectory("trajectory_camera.txt", io::Trajectory(frames.begin(), frames.end()));
#include <deque>
#include <functional>
#include <future>
#include <map>
#include <memory>
#include <optional>
#include <string>
#include <thread>
#include <vector>

#include "s3m/core/bounded_queue.hpp"
#include "s3m/core/camera.hpp"
#include "s3m/core/frame_state.hpp"
#include "s3m/core/rgbd_frame.hpp"
#include "s3m/slam/io/map_io.hpp"
#include "s3m/slam/local_mapping/local_mapper.hpp"
#include "s3m/slam/loop/loop_closer.hpp"
#include "s3m/slam/map/map.hpp"
#include "s3m/slam/slam_config.hpp"
#include "s3m/slam/tracking/tracker.hpp"

namespace s3m::slam {

struct TrackResult {
  int frame_index = 0;
  double t_s = 0;
  FrameState state = FrameState::kNotInitialized;
  SE3 T_w_c = SE3::Identity();  // camera-to-world at tracking time
  SE3 T_w_r = SE3::Identity();  // robot-to-world: robot_pose(T_w_c, T_c_r)
  bool keyframe = false;
  int n_inliers = 0;        // tracked map points
  double track_ms = 0;      // tracking only (features + pose), wall clock
  double track_cpu_ms = 0;  // process CPU time during tracking (all threads; in threaded mode
                            // it includes whatever local mapping ran meanwhile)
  double mapping_ms = 0;    // local mapping run inside track() (single-thread mode only)
  // The keyframe the pose is stored against (kNoKeyframe before the first one), and the pose
  // relative to it at tracking time (same world as T_w_c).
  KeyframeAnchor anchor;
  // Loop closures (and merges) the mapping stage finished since the previous frame, oldest first
  // (in single-thread mode: the one this frame's keyframe closed). They list world keyframes only
  // (sub-map 0); a merge into the world lists the joined ones, culled ones included.
  std::vector<LoopCorrection> corrections;
  // The sub-map the frame was tracked in (map_merge.hpp): 0 is the world; another is a new sub-map
  // started after relocalisation kept failing, and T_w_c, T_w_r are in its own frame until a merge
  // moves it into the world (camera_trajectory() then has the frame in the world).
  int submap = 0;
};

// A read of the whole map for the tracking side. Runs where the Map may be touched: inline in
// single-thread mode, on the mapping thread in threaded mode.
using MapQuery = std::function<void(const Map&)>;
// Read-only look at the map after each keyframe's mapping stage (tests pace local mapping with
// it); runs on the mapping thread in threaded mode.
using MappingObserver = std::function<void(const Map&, KeyframeId)>;

// One frame of a final trajectory: its time and pose (camera, robot or keyframe, after BA and loop
// closure; core's StampedPose, which io::write_tum_trajectory writes), which frame it is and how
// tracking went.
struct FramePose : StampedPose {
  int frame_index = 0;
  FrameState state = FrameState::kOk;
};

class System {
 public:
  // vocabulary: place recognition (config.loop_closing: loops, relocalisation); null = neither.
  System(const PinholeCamera& camera, const SlamConfig& config,
         std::shared_ptr<const features::Vocabulary> vocabulary = nullptr, MappingObserver observer = {});
  ~System();
  System(const System&) = delete;
  System& operator=(const System&) = delete;

  // 1 take mapped keyframes, 2 track, 3 relocalise when lost, 4 send a keyframe, 5 record.
  TrackResult track(const RgbdFrame& frame);
  // Threaded mode: waits until local mapping has processed every keyframe and stops its thread.
  // Then (mapper.final_global_ba) one bundle adjustment over the whole map. Idempotent; track()
  // must not be called afterwards.
  void finish();
  int n_global_ba_outliers() const { return n_global_ba_outliers_; }  // after finish()
  // The dense keyframe links measured (slam.mapper.dense_links) and whether the final global BA
  // used them; complete after finish().
  KeyframeLinkSummary keyframe_link_summary() const { return mapper_.link_summary(); }
  // After finish(): loop closures that reached tracking after the last track() (threaded mode).
  const std::vector<LoopCorrection>& late_corrections() const { return late_corrections_; }

  // Every tracked frame (from the first keyframe on), each expressed relative to its reference
  // keyframe's final pose — so BA, loop corrections and merges reach every frame. Call after
  // finish(). Frames and keyframes of a sub-map that never joined the world are left out.
  std::vector<FramePose> camera_trajectory() const;
  std::vector<FramePose> robot_trajectory() const;     // robot_pose(camera_trajectory(), T_c_r)
  std::vector<FramePose> keyframe_trajectory() const;  // live keyframes, camera poses

  // A map that lasts. Before the first track(): continue in the map saved at path by
  // save_map(); load_slam_map() checks it against this camera and vocabulary (ParseError naming
  // the file otherwise). The first frame is relocalised in it (BoW candidates, PnP, refinement)
  // and every pose is in its world frame; until a frame relocalises, frames are LOST. New
  // keyframes extend the map (their ids continue the loaded ones); with localize_only the map
  // stays exactly as loaded (no keyframes, points or point statistics, no final BA): tracking
  // moves its local map between the loaded keyframes and LOST frames relocalise against them.
  // Needs place recognition with relocalisation (a vocabulary).
  void load_map(const std::string& path, bool localize_only = false);
  // Writes the map with its BoW index and loop edges (map_io.hpp), atomically: the world only
  // (sub-maps that never merged into it are left out). Threaded mode: after finish(). Needs place
  // recognition (the index).
  void save_map(const std::string& path) const;
  bool localize_only() const { return localize_only_; }

  // The map. Threaded mode: only after finish() (the mapping thread owns it before that).
  const Map& map() const { return map_; }
  // Runs query on the map and waits for it. Threaded mode: the query travels through the keyframe
  // request queue, so it sees every keyframe sent before it, and what those keyframes produced is
  // handed to the tracker before this returns (tests use an empty query as a lockstep barrier).
  // Call from the tracking thread only (the one calling track()); rethrows the query's exception.
  void query_map(const MapQuery& query);
  const SlamConfig& config() const { return config_; }
  bool closes_loops() const { return closer_ && config_.loop_closing.enabled; }
  bool relocalises() const { return closer_ && config_.loop_closing.relocalisation; }
  int n_lost_frames() const { return n_lost_; }
  int n_relocalised_frames() const { return n_relocalised_; }
  int n_loops() const { return closer_ ? int(closer_->loop_edges().size()) : 0; }  // threaded: after finish()
  // Sub-maps (map_merge.hpp): whether this session starts them, how many it started, how many
  // merges it made (threaded: after finish()) and the keyframes outside the world (after finish()).
  bool makes_submaps() const;
  int n_new_submaps() const { return next_submap_ - 1; }
  int n_merges() const { return n_merges_; }
  int n_keyframes_outside_world() const { return map_.n_keyframes() - map_.n_keyframes_in(0); }
  // After finish(): tracked frames left out of camera_trajectory() (in sub-maps outside the world),
  // and whether the world became another sub-map at the end (loop_closing.merge.world "largest":
  // the map of the first frames then is one of those left out).
  int n_frames_outside_world() const;
  bool world_moved() const { return world_moved_; }

 private:
  struct FrameRecord;
  SE3 anchored_pose(const FrameRecord& rec) const;
  struct FrameRecord {
    int frame_index;
    double t_s;
    FrameState state;
    KeyframeAnchor anchor;
    std::vector<std::pair<KeyframeAnchor, double>> anchors;  // TrackerOutput::anchors
  };
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
  MappedKeyframe map_keyframe(KeyFrameRequest request);  // the mapping stage, either thread
  void take(MappedKeyframe mapped);
  void receive_mapped(int max_pending);
  bool receive_one();
  void take_tracking(const TrackerOutput& out, TrackResult& r) const;
  void receive_lagged();
  void send(MapperJob job);
  bool relocalise(const features::FrameFeatures& f, int frame_index, TrackResult& r);
  void move_local_map(const std::vector<PointId>& tracked_points, int frame_index);
  void mapping_loop();
  // Sub-maps (system_submaps.cpp). Tracking side: relocalise a LOST frame, else count the failure
  // and start a new sub-map when there were enough.
  void recover(const RgbdFrame& frame, TrackerOutput& out, TrackResult& r);
  // At finish(): makes the sub-map with the most tracked frames the world (merge.world).
  void choose_world();
  std::map<int, int> tracked_frames_per_submap() const;  // sub-map -> frames not LOST (after finish())
  // Mapping side: a request of a sub-map merged meanwhile is moved into the sub-map it joined; a
  // correction is handed on for the world's keyframes only (none: a loop inside another sub-map).
  int follow_merges(int submap) const;
  // With the merges.
  std::shared_ptr<const LocalMapSnapshot> snapshot(KeyframeId ref, int max_keyframes) const;
  void follow_merges(KeyFrameRequest& request) const;
  std::optional<LoopCorrection> note_correction(std::optional<LoopCorrection> c);

  PinholeCamera camera_;
  SlamConfig config_;
  Map map_;
  Tracker tracker_;
  LocalMapper mapper_;
  std::optional<LoopCloser> closer_;  // place recognition (loop closing and/or relocalisation)
  std::shared_ptr<const features::Vocabulary> vocabulary_;
  bool localize_only_ = false;  // a loaded map, frozen
  MappingObserver observer_;
  std::vector<FrameRecord> records_;
  std::vector<LoopCorrection> corrections_;  // received, not yet returned by track()
  std::vector<LoopCorrection> late_corrections_;
  int n_lost_ = 0, n_relocalised_ = 0;
  int n_failed_relocalisations_ = 0;  // consecutive LOST frames that did not relocalise
  int next_submap_ = 1;               // tracking side: the id a new sub-map gets
  int frames_in_submap_ = 0;          // tracking side: frames tracked in the current sub-map
  bool world_loaded_ = false;         // load_map(): the loaded map is the world for good
  bool world_moved_ = false;          // choose_world() made another sub-map the world
  // Mapping side: merged sub-map -> (the sub-map it joined, T_into_from).
  std::map<int, std::pair<int, SE3>> merged_into_;
  int n_merges_ = 0;
  // Threaded mode.
  BoundedQueue<MapperJob> requests_;
  BoundedQueue<MappedKeyframe> mapped_;
  std::thread mapping_thread_;
  int n_sent_ = 0, n_received_ = 0;  // keyframe requests sent / answered (tracking thread only)
  long n_tracked_ = 0;               // track() calls (tracking thread only)
  std::deque<long> sent_at_;         // the track() call that sent each unanswered keyframe
  bool finished_ = false;
  int n_global_ba_outliers_ = 0;
};

}  // namespace s3m::slam
