#pragma once
// The tracking side of slam::System: the Tracker, relocalisation and new sub-maps, the record of
// every frame's pose, and the tracking end of the two bounded queues to the mapping stage.
// Everything here belongs to the thread that calls track(). It reaches the map only through
// query_map() (which runs on the mapping thread in threaded mode) and, in single-thread mode,
// by running the mapping stage inline.
#include <deque>
#include <memory>
#include <optional>
#include <utility>
#include <vector>

#include "s3m/core/bounded_queue.hpp"
#include "s3m/core/frame_state.hpp"
#include "s3m/core/rgbd_frame.hpp"
#include "s3m/slam/mapping_back_end.hpp"
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
  // The sub-map the frame was tracked in (loop/map_merge.hpp): 0 is the world; another is a new
  // sub-map started after relocalisation kept failing, and T_w_c, T_w_r are in its own frame until
  // a merge moves it into the world (System::camera_trajectory() then has the frame in the world).
  int submap = 0;
};

// One tracked frame as the final trajectory needs it: its pose relative to keyframes.
struct FrameRecord {
  int frame_index;
  double t_s;
  FrameState state;
  KeyframeAnchor anchor;
  std::vector<std::pair<KeyframeAnchor, double>> anchors;  // TrackerOutput::anchors
};

class TrackingFrontEnd {
 public:
  // back: the mapping stage, called inline in single-thread mode and reached through query_map()
  // otherwise. jobs / mapped: the queues to and from the mapping thread (threaded mode).
  TrackingFrontEnd(const PinholeCamera& camera, const SlamConfig& config, MappingBackEnd& back,
                   BoundedQueue<MapperJob>& jobs, BoundedQueue<MappedKeyframe>& mapped);

  // 1 take mapped keyframes, 2 track, 3 relocalise when lost, 4 send a keyframe, 5 record.
  TrackResult track(const RgbdFrame& frame);
  // Runs query on the map and waits for it (see System::query_map).
  void query_map(const MapQuery& query);
  // The mapping thread has stopped: take every answer still queued. Queries run inline from now on.
  void finish();
  // Before the first frame: continue in the back end's loaded map.
  void continue_map(KeyframeId next_keyframe_id, bool localize_only);

  bool localize_only() const { return localize_only_; }
  bool makes_submaps() const;
  bool before_first_frame() const { return records_.empty() && n_sent_ == 0; }
  const std::vector<FrameRecord>& records() const { return records_; }
  // Loop corrections received and not yet returned by track() (after finish(): the late ones).
  std::vector<LoopCorrection> take_corrections();
  int n_lost_frames() const { return n_lost_; }
  features::DepthNoiseEstimate depth_noise() const { return tracker_.depth_noise(); }
  int n_relocalised_frames() const { return n_relocalised_; }
  int n_new_submaps() const { return next_submap_ - 1; }

 private:
  void take(MappedKeyframe mapped);
  bool receive_one();
  void receive_mapped(int max_pending);
  void receive_lagged();
  void send(MapperJob job);
  void send_keyframe(KeyFrameRequest request, TrackResult& r);
  void take_tracking(const TrackerOutput& out, TrackResult& r) const;
  bool relocalise(const features::FrameFeatures& f, int frame_index, TrackResult& r);
  void move_local_map(const std::vector<PointId>& tracked_points, int frame_index);
  // Relocalise a LOST frame, else count the failure and start a new sub-map when there were enough.
  void recover(const RgbdFrame& frame, TrackerOutput& out, TrackResult& r);
  void record(const RgbdFrame& frame, TrackerOutput& out, TrackResult& r);

  SlamConfig config_;
  MappingBackEnd& back_;
  BoundedQueue<MapperJob>& jobs_;
  BoundedQueue<MappedKeyframe>& mapped_;
  Tracker tracker_;
  bool localize_only_ = false;  // a loaded map, frozen
  bool finished_ = false;
  std::vector<FrameRecord> records_;
  std::vector<LoopCorrection> corrections_;  // received, not yet returned by track()
  int n_lost_ = 0, n_relocalised_ = 0;
  int n_failed_relocalisations_ = 0;  // consecutive LOST frames that did not relocalise
  int next_submap_ = 1;               // the id a new sub-map gets
  int frames_in_submap_ = 0;          // frames tracked in the current sub-map
  int n_sent_ = 0, n_received_ = 0;   // keyframe requests sent / answered
  long n_tracked_ = 0;                // track() calls
  std::deque<long> sent_at_;          // the track() call that sent each unanswered keyframe
};

}  // namespace s3m::slam
