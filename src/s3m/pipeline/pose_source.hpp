#pragma once
// Where the pipeline's camera poses come from: the SLAM system (the normal case) or, for
// evaluating segmentation and mapping in isolation, the dataset's ground truth. One interface so
// the pipeline's process() does not care which.
#include <functional>
#include <map>
#include <memory>
#include <string>

#include "s3m/core/rgbd_frame.hpp"
#include "s3m/io/trajectory.hpp"
#include "s3m/pipeline/keyframe_store.hpp"

namespace s3m::pipeline {

struct TrackOutput {
  SE3 T_w_c = SE3::Identity();  // camera -> world
  std::string state;            // tracking state as SLAM names it ("OK", "LOST", "RELOCALISED", ...)
  bool ok = false;              // pose usable for mapping
  bool keyframe = false;        // this frame became a keyframe
  KeyframeId keyframe_id = -1;  // its id when keyframe, else the current reference keyframe (-1: none)
  SE3 T_w_kf = SE3::Identity(); // pose of keyframe_id (when >= 0)
};

// Corrected keyframe poses (T_w_kf) after a loop closure or a global optimisation.
using CorrectionListener = std::function<void(const std::map<KeyframeId, SE3>&)>;

class PoseSource {
 public:
  virtual ~PoseSource() = default;
  // Estimates the pose of the next frame (frames arrive in order, from one thread).
  virtual TrackOutput track(const RgbdFrame& frame) = 0;
  // Called (from any thread) whenever keyframe poses are corrected. Set before the first track().
  virtual void set_correction_listener(CorrectionListener listener) = 0;
  // Ends background work (local mapping, loop closing) so the results below are final.
  virtual void finish() = 0;
  // Final per-frame camera trajectory (after all optimisation), and final keyframe poses.
  virtual io::Trajectory camera_trajectory() const = 0;
  virtual io::Trajectory keyframe_trajectory() const = 0;
  virtual std::map<KeyframeId, SE3> keyframe_poses() const = 0;
  virtual std::string name() const = 0;
};

// Ground-truth poses (T_w_c from the dataset). Keyframes are chosen by motion, like a SLAM
// system would: when the camera moved more than keyframe_dist_m or turned more than keyframe_angle_rad
// since the last keyframe. Frames without a ground-truth pose within max_dt_s are reported "NO_GT".
struct GroundTruthPosesConfig {
  double keyframe_dist_m = 0.10;   // [m]
  double keyframe_angle_rad = 0.17;  // [rad] (~10 deg)
  double max_dt_s = 0.02;          // [s]
};
std::unique_ptr<PoseSource> make_ground_truth_poses(io::Trajectory groundtruth, GroundTruthPosesConfig config = {});

}  // namespace s3m::pipeline
