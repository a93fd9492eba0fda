#pragma once
// How a frame's pose came about: one set of states for SLAM, the pipeline's pose sources and their
// outputs. Code compares the enum; the names below appear only where a state is written out
// (frames.txt, metrics.json, logs, the ROS node), so they must never change.

namespace s3m {

enum class FrameState {
  kNotInitialized,  // SLAM has no map yet: too few points with depth to start one
  kOk,              // tracked (ground truth: a pose at the frame's time)
  kLost,            // tracking failed: the pose is only a motion-model guess, left out of trajectories
  kRelocalised,     // was LOST; found again against the whole map
  kOdometry,        // the map could not track it: posed by dense depth odometry from the last frame
  kSubmap,          // tracked in a SLAM sub-map that has not joined the world (yet)
  kNoGroundTruth,   // ground-truth poses: none within GroundTruthPosesConfig::max_dt_s of the frame
};

constexpr const char* to_string(FrameState s) {
  switch (s) {
    case FrameState::kNotInitialized: return "NOT_INITIALIZED";
    case FrameState::kOk: return "OK";
    case FrameState::kLost: return "LOST";
    case FrameState::kRelocalised: return "RELOCALISED";
    case FrameState::kOdometry: return "ODOMETRY";
    case FrameState::kSubmap: return "SUBMAP";
    case FrameState::kNoGroundTruth: return "NO_GT";
  }
  return "?";
}

}  // namespace s3m
