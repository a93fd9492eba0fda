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
#include <map>
#include <memory>
#include <string>
#include <thread>
#include <vector>

#include "s3m/core/bounded_queue.hpp"
#include "s3m/core/camera.hpp"
#include "s3m/core/frame_state.hpp"
#include "s3m/core/rgbd_frame.hpp"
#include "s3m/slam/mapping_back_end.hpp"
#include "s3m/slam/slam_config.hpp"
#include "s3m/slam/tracking_front_end.hpp"

namespace s3m::slam {

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
  int n_global_ba_outliers() const { return back_.n_global_ba_outliers(); }  // after finish()
  // The dense keyframe links measured (slam.mapper.dense_links) and whether the final global BA
  // used them; complete after finish().
  KeyframeLinkSummary keyframe_link_summary() const { return back_.link_summary(); }
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
  bool localize_only() const { return front_.localize_only(); }

  // The map. Threaded mode: only after finish() (the mapping thread owns it before that).
  const Map& map() const { return back_.map(); }
  // Runs query on the map and waits for it. Threaded mode: the query travels through the keyframe
  // request queue, so it sees every keyframe sent before it, and what those keyframes produced is
  // handed to the tracker before this returns (tests use an empty query as a lockstep barrier).
  // Call from the tracking thread only (the one calling track()); rethrows the query's exception.
  void query_map(const MapQuery& query);
  const SlamConfig& config() const { return config_; }
  bool closes_loops() const { return back_.closes_loops(); }
  bool relocalises() const { return back_.relocalises(); }
  int n_lost_frames() const { return front_.n_lost_frames(); }
  // What tracking learnt about the depth sensor (features/depth_noise_estimator.hpp); tracking
  // thread, or after finish().
  features::DepthNoiseEstimate depth_noise() const { return front_.depth_noise(); }
  int n_relocalised_frames() const { return front_.n_relocalised_frames(); }
  int n_loops() const { return back_.n_loops(); }  // threaded: after finish()
  // Sub-maps (map_merge.hpp): whether this session starts them, how many it started, how many
  // merges it made (threaded: after finish()) and the keyframes outside the world (after finish()).
  bool makes_submaps() const { return front_.makes_submaps(); }
  int n_new_submaps() const { return front_.n_new_submaps(); }
  int n_merges() const { return back_.n_merges(); }
  int n_keyframes_outside_world() const { return map().n_keyframes() - map().n_keyframes_in(0); }
  // After finish(): tracked frames left out of camera_trajectory() (in sub-maps outside the world),
  // and whether the world became another sub-map at the end (loop_closing.merge.world "largest":
  // the map of the first frames then is one of those left out).
  int n_frames_outside_world() const;
  bool world_moved() const { return world_moved_; }

 private:
  SE3 anchored_pose(const FrameRecord& rec) const;
  // At finish(): makes the sub-map with the most tracked frames the world (merge.world).
  void choose_world();
  std::map<int, int> tracked_frames_per_submap() const;  // sub-map -> frames not LOST (after finish())

  // Each side's state is in its own type: the mapping stage's (the Map) on the mapping thread in
  // threaded mode, the tracking side's on the thread calling track(); the queues join them.
  PinholeCamera camera_;
  SlamConfig config_;
  MappingBackEnd back_;
  BoundedQueue<MapperJob> requests_;
  BoundedQueue<MappedKeyframe> mapped_;
  TrackingFrontEnd front_;
  std::thread mapping_thread_;  // threaded mode: runs back_.serve()
  std::vector<LoopCorrection> late_corrections_;
  bool finished_ = false;
  bool world_loaded_ = false;  // load_map(): the loaded map is the world for good
  bool world_moved_ = false;   // choose_world() made another sub-map the world
};

}  // namespace s3m::slam
