#pragma once
// Identifiers and small value types shared by the SLAM stages.
#include <array>
#include <cstdint>

#include "s3m/core/keyframe_id.hpp"

namespace s3m::slam {

using PointId = std::int64_t;                // map point id, increasing in creation order
constexpr std::int64_t kNoId = kNoKeyframe;  // no keyframe / no point

using Descriptor = std::array<std::uint8_t, 32>;  // one ORB descriptor

}  // namespace s3m::slam
