// The depth-scale check before a run: the median of the sample frames' valid depth, and a warning
// naming the factor that would make it plausible when it is not.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>

#include "s3m/pipeline/depth_scale.hpp"

namespace s3m::pipeline {
namespace {

RgbdFrame frame_at(float depth_m) {
  RgbdFrame f;
  f.depth_m = cv::Mat(48, 64, CV_32F, cv::Scalar(depth_m));
  return f;
}

TEST(DepthScale, MedianOfValidDepthOverTheSample) {
  // 1 m, 2 m and 3 m frames, the last with holes (0) and NaN that do not count: median 2 m.
  RgbdFrame holes = frame_at(3.0f);
  holes.depth_m(cv::Rect(0, 0, 64, 8)).setTo(0.0f);
  holes.depth_m(cv::Rect(0, 8, 64, 8)).setTo(std::numeric_limits<float>::quiet_NaN());
  const DepthScaleCheck c = check_depth_scale({frame_at(1.0f), frame_at(2.0f), holes}, 5000);
  EXPECT_EQ(c.frames, 3u);
  EXPECT_FLOAT_EQ(c.median_m, 2.0f);
  EXPECT_EQ(c.warning, "");
}

TEST(DepthScale, TooNearNamesTheMillimetreFactor) {
  // Millimetre depth of a room 1.5 m away read as TUM's 5000 per metre: 0.3 m.
  const DepthScaleCheck c = check_depth_scale({frame_at(0.3f), frame_at(0.3f)}, 5000);
  EXPECT_FLOAT_EQ(c.median_m, 0.3f);
  EXPECT_NE(c.warning.find("median depth 0.30 m over 2 frame(s) with depth factor 5000: nearer than"), std::string::npos)
      << c.warning;
  EXPECT_NE(c.warning.find("with depth factor 1000 it would be 1.50 m"), std::string::npos) << c.warning;
}

TEST(DepthScale, TooFarNamesTheTumFactor) {
  const DepthScaleCheck c = check_depth_scale({frame_at(20.0f)}, 1000);
  EXPECT_NE(c.warning.find("median depth 20.00 m over 1 frame(s) with depth factor 1000: farther than"), std::string::npos)
      << c.warning;
  EXPECT_NE(c.warning.find("with depth factor 5000 it would be 4.00 m"), std::string::npos) << c.warning;
  // 60 m: neither common factor makes it plausible, so none is suggested.
  EXPECT_EQ(check_depth_scale({frame_at(60.0f)}, 1000).warning.find("it would be"), std::string::npos);
}

TEST(DepthScale, NoDepthAtAllOrNoFrames) {
  const DepthScaleCheck none = check_depth_scale({frame_at(0.0f)}, 1000);
  EXPECT_EQ(none.median_m, 0);
  EXPECT_NE(none.warning.find("no valid depth in 1 sample frame(s)"), std::string::npos) << none.warning;
  const DepthScaleCheck empty = check_depth_scale({}, 1000);
  EXPECT_EQ(empty.frames, 0u);
  EXPECT_EQ(empty.warning, "");
}

}  // namespace
}  // namespace s3m::pipeline
