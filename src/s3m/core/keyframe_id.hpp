#pragma once
// The one keyframe identifier of s3m and the one "pose relative to a keyframe" type, shared by
// slam (which creates keyframes) and pipeline (which anchors its kept clouds to them).
#include <cstdint>

#include "s3m/core/se3.hpp"

namespace s3m {

// Assigned by SLAM in creation order (0, 1, 2, ...), never reused; a culled keyframe keeps its id.
// The ground-truth pose source numbers its motion keyframes the same way.
using KeyframeId = std::int64_t;
inline constexpr KeyframeId kNoKeyframe = -1;

// A pose stored relative to a keyframe, so that it follows the keyframe when SLAM moves it
// (bundle adjustment, loop closure): T_w_c = T_w_kf(keyframe) * T_kf_c.
struct KeyframeAnchor {
  KeyframeId keyframe = kNoKeyframe;
  SE3 T_kf_c = SE3::Identity();  // camera -> keyframe frame [m]
};

}  // namespace s3m
