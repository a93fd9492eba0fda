#pragma once
// s3m::slam::System — the library entry point for RGB-D SLAM (thin: wires Tracker, LocalMapper
// and the Map). Single-thread mode runs local mapping inside track() right after a keyframe and
// is deterministic; threaded mode runs local mapping in its own thread, connected to tracking by
// two bounded queues (keyframe requests one way, map snapshots the other).
//
//   slam::System slam(camera, slam::load_slam_config("config/slam_default.yaml"));
//   for (const RgbdFrame& f : frames) { auto r = slam.track(f); ... r.T_w_c, r.state ... }
//   slam.finish();
//   slam::write_tum_trajectory("trajectory_camera.txt", slam.camera_trajectory());
#include <functional>
#include <future>
#include <memory>
#include <optional>
#include <string>
#include <thread>
#include <vector>

#include "s3m/core/bounded_queue.hpp"
#include "s3m/core/camera.hpp"
#include "s3m/core/rgbd_frame.hpp"
#include "s3m/slam/local_mapper.hpp"
#include "s3m/slam/map.hpp"
#include "s3m/slam/slam_config.hpp"
#include "s3m/slam/tracker.hpp"

namespace s3m::slam {

struct TrackResult {
  int frame_index = 0;
  double t_s = 0;
  TrackState state = TrackState::kNotInitialized;
  SE3 T_w_c = SE3::Identity();  // camera-to-world at tracking time
  SE3 T_w_r = SE3::Identity();  // robot-to-world: T_w_c * T_c_r
  bool keyframe = false;
  int n_inliers = 0;            // tracked map points
  double track_ms = 0;          // tracking only (features + pose), wall clock
  double track_cpu_ms = 0;      // process CPU time during tracking (all threads; in threaded mode
                                // it includes whatever local mapping ran meanwhile)
  double mapping_ms = 0;        // local mapping run inside track() (single-thread mode only)
  KfId ref_kf = kNoId;          // keyframe the pose is stored against (kNoId before the first one)
  SE3 T_ref_c = SE3::Identity();  // pose relative to ref_kf at tracking time (same world as T_w_c)
};

// A read of the whole map for the tracking side (relocalisation). Runs where the Map may be
// touched: inline in single-thread mode, on the local-mapping thread in threaded mode.
using MapQuery = std::function<void(const Map&)>;

struct StampedPose {
  double t_s = 0;
  int frame_index = 0;
  SE3 T_w_x = SE3::Identity();  // camera, robot or keyframe pose in the world [m]
  TrackState state = TrackState::kOk;
};

class System {
 public:
  System(const PinholeCamera& camera, const SlamConfig& config);
  ~System();
  System(const System&) = delete;
  System& operator=(const System&) = delete;

  TrackResult track(const RgbdFrame& frame);
  // Threaded mode: waits until local mapping has processed every keyframe and stops its thread.
  // Then (mapper.final_global_ba) one bundle adjustment over the whole map. Idempotent; track()
  // must not be called afterwards.
  void finish();
  int n_global_ba_outliers() const { return n_global_ba_outliers_; }  // after finish()

  // Every tracked frame (from the first keyframe on), each expressed relative to its reference
  // keyframe's final pose — so BA and loop corrections reach every frame. Call after finish().
  std::vector<StampedPose> camera_trajectory() const;
  std::vector<StampedPose> robot_trajectory() const;    // camera_trajectory() * T_c_r
  std::vector<StampedPose> keyframe_trajectory() const;  // live keyframes, camera poses

  // The map. Threaded mode: only after finish() (the mapping thread owns it before that).
  const Map& map() const { return map_; }
  // Runs in the mapping stage after each keyframe (loop closing plugs in here). Set before track().
  void set_keyframe_hook(LocalMapper::KeyFrameHook hook) { mapper_.set_keyframe_hook(std::move(hook)); }
  // Runs query on the map and waits for it. Threaded mode: the query travels through the keyframe
  // request queue, so it sees every keyframe sent before it, and the snapshots those keyframes
  // produced are handed to the tracker before this returns (a snapshot the query makes is newer).
  // Call from the tracking thread only (the one calling track()); rethrows the query's exception.
  void query_map(const MapQuery& query);
  // Relocalisation hook: frame_index (the frame track() just returned LOST) was relocalised at
  // T_kf_c relative to keyframe kf; its trajectory record is replaced accordingly.
  void note_relocalised(int frame_index, KfId kf, const SE3& T_kf_c);
  Tracker& tracker() { return tracker_; }
  const SlamConfig& config() const { return config_; }
  int n_lost_frames() const { return n_lost_; }
  int n_relocalised_frames() const { return n_relocalised_; }

 private:
  struct FrameRecord {
    int frame_index;
    double t_s;
    TrackState state;
    KfId ref_kf;
    SE3 T_ref_c;
  };
  // What the local-mapping thread receives: a keyframe to map, or a map query to answer.
  struct MapperJob {
    std::optional<KeyFrameRequest> keyframe;
    MapQuery query;
    std::shared_ptr<std::promise<void>> done;  // set once the query ran (value or its exception)
  };
  void drain_snapshots();
  void mapping_loop();

  PinholeCamera camera_;
  SlamConfig config_;
  Map map_;
  Tracker tracker_;
  LocalMapper mapper_;
  std::vector<FrameRecord> records_;
  int n_lost_ = 0, n_relocalised_ = 0;
  // Threaded mode.
  BoundedQueue<MapperJob> requests_;
  BoundedQueue<std::shared_ptr<const LocalMapSnapshot>> snapshots_;
  std::thread mapping_thread_;
  int n_sent_ = 0, n_received_ = 0;
  bool finished_ = false;
  int n_global_ba_outliers_ = 0;
};

// The paper's calibration equation: robot-to-world from camera-to-world and the robot-to-camera
// calibration T_c_r (maps robot-frame points into the camera frame).
inline SE3 robot_pose(const SE3& T_w_c, const SE3& T_c_r) { return T_w_c * T_c_r; }

// TUM format: "t tx ty tz qx qy qz qw" per line, with a header comment. Throws s3m::Error when
// the file cannot be written.
void write_tum_trajectory(const std::string& path, const std::vector<StampedPose>& poses);

}  // namespace s3m::slam
