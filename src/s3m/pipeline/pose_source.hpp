#pragma once
// Where the pipeline's camera poses come from: the SLAM system (the normal case) or, for
// evaluating segmentation and mapping in isolation, the dataset's ground truth. One interface so
// the pipeline's process() does not care which.
#include <map>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "s3m/core/frame_state.hpp"
#include "s3m/core/rgbd_frame.hpp"
#include "s3m/features/depth_noise_estimator.hpp"
#include "s3m/io/trajectory.hpp"
#include "s3m/pipeline/keyframe_store.hpp"

namespace s3m::pipeline {

// Corrected keyframe poses T_w_kf (after a loop closure or a global optimisation).
using KeyframePoses = std::map<KeyframeId, SE3>;

struct TrackOutput {
  SE3 T_w_c = SE3::Identity();                     // camera -> world
  FrameState state = FrameState::kNotInitialized;  // how the pose came about
  bool ok = false;                                 // pose usable for mapping
  bool keyframe = false;                           // this frame became a keyframe
  // The keyframe this frame's pose is relative to (this frame's own when keyframe; kNoKeyframe:
  // none yet), T_kf_c in the same world as T_w_c.
  KeyframeAnchor anchor;
  // Corrections made since the previous frame, oldest first. They travel with the frame, so the
  // mapping stage applies them in tracking order (through the pipeline's frame queues). A
  // correction lists world keyframes only; a keyframe listed for the first time joins the world
  // (a merge of a sub-map, below).
  std::vector<KeyframePoses> corrections;
  // The pose is in a sub-map of its own, not (yet) in the world: SLAM started a new map after
  // relocalisation kept failing (slam/map_merge.hpp). Its keyframe clouds are kept, not mapped,
  // until a correction lists their keyframes (the sub-map merged into the world).
  bool detached = false;
  // SLAM's tracking alone (features and pose) [ms, wall clock], without the local mapping a
  // single-thread run does inside track(); < 0 where there is no tracker (ground-truth poses).
  double tracking_ms = -1;
};

// The SLAM side of a pose source: a map that outlasts the run (saved, and continued in by a later
// one) and may be split in sub-maps (slam/map_merge.hpp). Only the SLAM source has one
// (PoseSource::session_map()).
class SessionMap {
 public:
  // Before the first track(): continue in the SLAM map saved at path (localize_only: without
  // changing it).
  virtual void load_map(const std::string& path, bool localize_only) = 0;
  // After finish(): write the map to path; false when there is none to write.
  virtual bool save_map(const std::string& path) const = 0;
  // After finish(): sub-maps started when relocalisation kept failing, merges made, and keyframes
  // still outside the world (neither reported nor saved). world_moved: the world became another
  // sub-map at the end (the one with the most tracked frames); frames_outside_world: tracked
  // frames left out of the trajectory.
  struct Submaps {
    int started = 0, merges = 0, keyframes_outside_world = 0, frames_outside_world = 0;
    bool world_moved = false;
  };
  virtual Submaps submaps() const = 0;
  // After finish(): what tracking learnt about the depth sensor (noise curve, colour-depth offset).
  virtual features::DepthNoiseEstimate depth_noise() const = 0;
  // After finish(), when the world moved (Submaps::world_moved): every keyframe now in it, culled
  // ones included, with its pose; every other keyframe has left it. Otherwise nothing.
  virtual std::optional<KeyframePoses> moved_world() const = 0;

 protected:
  ~SessionMap() = default;  // owned as the PoseSource it belongs to, never through this interface
};

class PoseSource {
 public:
  virtual ~PoseSource() = default;
  // Estimates the pose of the next frame (frames arrive in order, from one thread).
  virtual TrackOutput track(const RgbdFrame& frame) = 0;
  // Ends background work (local mapping, loop closing) so the results below are final; returns
  // the corrections made after the last track() output.
  virtual std::vector<KeyframePoses> finish() = 0;
  // Final per-frame camera trajectory (after all optimisation), and final keyframe poses.
  virtual io::Trajectory camera_trajectory() const = 0;
  virtual io::Trajectory keyframe_trajectory() const = 0;
  virtual KeyframePoses keyframe_poses() const = 0;
  virtual std::string name() const = 0;
  // The SLAM map the poses are in; nullptr when the source has none (ground truth).
  virtual SessionMap* session_map() { return nullptr; }
  virtual const SessionMap* session_map() const { return nullptr; }
};

// Before the first track(): poses continue in the SLAM map saved at path (--map). A source without
// a session map refuses, naming itself.
void load_session_map(PoseSource& poses, const std::string& path, bool localize_only);

// Ground-truth poses (T_w_c from the dataset). Keyframes are chosen by motion, like a SLAM
// system would: when the camera moved more than keyframe_dist_m or turned more than keyframe_angle_rad
// since the last keyframe. Frames without a ground-truth pose within max_dt_s are kNoGroundTruth.
struct GroundTruthPosesConfig {
  double keyframe_dist_m = 0.10;     // [m]
  double keyframe_angle_rad = 0.17;  // [rad] (~10 deg)
  double max_dt_s = 0.02;            // [s]
};
std::unique_ptr<PoseSource> make_ground_truth_poses(io::Trajectory groundtruth,
                                                    GroundTruthPosesConfig config = {});

}  // namespace s3m::pipeline
