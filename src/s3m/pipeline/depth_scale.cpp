#include "s3m/pipeline/depth_scale.hpp"

#include <algorithm>
#include <cmath>

#include <fmt/format.h>
#include <spdlog/spdlog.h>

#include "s3m/core/error.hpp"

namespace s3m::pipeline {

DepthScaleCheck check_depth_scale(const std::vector<RgbdFrame>& sample, double depth_factor) {
  DepthScaleCheck c;
  std::vector<float> z;
  for (const RgbdFrame& f : sample) {
    if (f.depth_m.empty()) continue;
    ++c.frames;
    // Every 4th pixel in both directions: the median of ~20k values per VGA frame is plenty.
    for (int v = 0; v < f.depth_m.rows; v += 4)
      for (int u = 0; u < f.depth_m.cols; u += 4)
        if (const float d = f.depth_m.at<float>(v, u); std::isfinite(d) && d > 0) z.push_back(d);
  }
  if (c.frames == 0) return c;
  if (z.empty()) {
    c.warning = fmt::format("depth scale check: no valid depth in {} sample frame(s) (all 0): is it a depth image?", c.frames);
    return c;
  }
  std::nth_element(z.begin(), z.begin() + z.size() / 2, z.end());
  c.median_m = z[z.size() / 2];
  if (c.median_m >= kNearestMedianM && c.median_m <= kFarthestMedianM) return c;
  c.warning = fmt::format("depth scale check: median depth {:.2f} m over {} frame(s) with depth factor {:g}: {} than "
                          "an RGB-D camera usually sees a room",
                          c.median_m, c.frames, depth_factor, c.median_m < kNearestMedianM ? "nearer" : "farther");
  for (const double factor : {1000.0, 5000.0}) {
    const double other = c.median_m * depth_factor / factor;
    if (factor != depth_factor && other >= kNearestMedianM && other <= kFarthestMedianM)
      c.warning += fmt::format("; with depth factor {:g} it would be {:.2f} m (camera.yaml depth_factor, or the "
                               "preset's dataset.camera)", factor, other);
  }
  return c;
}

std::vector<RgbdFrame> sample_frames(const FrameSource& source, std::vector<std::string>* unreadable) {
  std::vector<RgbdFrame> sample;
  for (std::size_t i = 0; i < std::min<std::size_t>(source.size(), 120) && sample.size() < 6; i += 20) {
    try {
      sample.push_back(source.load(i));
    } catch (const ParseError& e) {  // the run skips it too (run.cpp); the checks use the others
      spdlog::warn("run: depth checks: frame {} not used: {}", i, e.what());
      if (unreadable) unreadable->push_back(fmt::format("frame {}: {}", i, e.what()));
    }
  }
  return sample;
}

}  // namespace s3m::pipeline
