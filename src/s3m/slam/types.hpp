#pragma once
// Identifiers and small value types shared by the SLAM stages.
#include <array>
#include <cstdint>

#include "s3m/core/keyframe_id.hpp"

namespace s3m::slam {

using PointId = std::int64_t;  // map point id, increasing in creation order
constexpr std::int64_t kNoId = kNoKeyframe;  // no keyframe / no point

using Descriptor = std::array<std::uint8_t, 32>;  // one ORB descriptor

// kRelocalised: the frame was LOST for tracking and relocalised against the whole map.
// kOdometry: the map could not track the frame; its pose is the last frame's moved by dense depth
// odometry (TrackerConfig::odometry_frames), in the trajectory like a tracked frame.
enum class TrackState { kNotInitialized, kOk, kLost, kRelocalised, kOdometry };

inline const char* to_string(TrackState s) {
  switch (s) {
    case TrackState::kNotInitialized: return "NOT_INITIALIZED";
    case TrackState::kOk: return "OK";
    case TrackState::kLost: return "LOST";
    case TrackState::kRelocalised: return "RELOCALISED";
    case TrackState::kOdometry: return "ODOMETRY";
  }
  return "?";
}

}  // namespace s3m::slam
