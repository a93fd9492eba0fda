#pragma once
// A depth factor that is off (TUM's 5000 on millimetre depth, or 1000 on TUM's) does not fail: the
// run goes through and SLAM, map and all come out 5x too small or too large. Checked before the
// first frame from a few frames' median depth, and said as a warning (close-range and very large
// scenes are legitimate, so the run goes on), in the log and in metrics.json.
#include <string>
#include <vector>

#include "s3m/core/rgbd_frame.hpp"
#include "s3m/pipeline/frame_source.hpp"

namespace s3m::pipeline {

struct DepthScaleCheck {
  double median_m = 0;   // of the valid (> 0, finite) depth pixels of the sample [m]; 0 = none
  std::size_t frames = 0;
  std::string warning;   // "" when the median is plausible for an RGB-D camera indoors
};

// Plausible: a median in [kNearestMedianM, kFarthestMedianM]. Outside, the warning names the depth
// factor in use and what the common factors 1000 (millimetres) and 5000 (TUM) would make of it.
inline constexpr double kNearestMedianM = 0.4;
inline constexpr double kFarthestMedianM = 6.0;
DepthScaleCheck check_depth_scale(const std::vector<RgbdFrame>& sample, double depth_factor);

// Frames 0, 20, 40, ... (at most 6, within the first 120) of `source`; an unreadable one is left
// out with a warning (the run skips it too) and, when `unreadable` is given, its error added there.
std::vector<RgbdFrame> sample_frames(const FrameSource& source, std::vector<std::string>* unreadable = nullptr);

}  // namespace s3m::pipeline
