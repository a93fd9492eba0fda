// Depth-to-colour registration from the images alone: synthetic frames whose depth is exactly
// registered, or drawn through a known scale and shift (as a Kinect v1 depth camera beside its
// colour camera), must be told apart and the model recovered.
#include <random>

#include <gtest/gtest.h>
#include <opencv2/imgproc.hpp>

#include "s3m/features/depth_registration.hpp"

namespace s3m::features {
namespace {

constexpr double kCx = 320, kCy = 240;

// Boxes at 1-2 m in front of a wall at 3 m. Colour: each box and the wall one flat colour, so
// the colour edges are the box borders. Depth: the same boxes, drawn where the model
// "depth pixel = c + s * (colour pixel - c) + (dx, dy)" puts them.
RgbdFrame boxes_frame(unsigned seed, double s, double dx, double dy) {
  RgbdFrame f;
  f.rgb = cv::Mat(480, 640, CV_8UC3, cv::Scalar(40, 40, 40));
  f.depth_m = cv::Mat(480, 640, CV_32F, cv::Scalar(3.0f));
  std::mt19937 rng(seed);
  std::uniform_int_distribution<int> x(40, 520), y(40, 360), size(40, 110), grey(150, 250);
  std::uniform_real_distribution<float> z(1.0f, 2.0f);
  for (int b = 0; b < 6; ++b) {
    const int u0 = x(rng), v0 = y(rng), w = size(rng), h = size(rng);
    const int g = grey(rng);
    const cv::Scalar colour(g, g, g);
    cv::rectangle(f.rgb, cv::Rect(u0, v0, w, h), colour, cv::FILLED);
    auto to_depth = [&](double u, double v) {
      return cv::Point(static_cast<int>(std::lround(kCx + s * (u - kCx) + dx)),
                       static_cast<int>(std::lround(kCy + s * (v - kCy) + dy)));
    };
    const cv::Point p0 = to_depth(u0, v0), p1 = to_depth(u0 + w, v0 + h);
    cv::rectangle(f.depth_m, cv::Rect(p0, p1), cv::Scalar(z(rng)), cv::FILLED);
  }
  return f;
}

std::vector<RgbdFrame> frames(double s, double dx, double dy) {
  return {boxes_frame(1, s, dx, dy), boxes_frame(2, s, dx, dy), boxes_frame(3, s, dx, dy)};
}

TEST(DepthRegistration, RegisteredDepthFitsTheIdentity) {
  const auto c = check_depth_registration(frames(1.0, 0, 0), kCx, kCy);
  EXPECT_TRUE(c.registered) << c.summary;
  EXPECT_GT(c.fit.n_edges, 300);
  EXPECT_NEAR(c.fit.scale, 1.0, 0.005);
  EXPECT_NEAR(c.fit.dx_px, 0.0, 1.0);
  EXPECT_NEAR(c.fit.dy_px, 0.0, 1.0);
  // Every depth edge is on (or one pixel beside) a colour edge.
  EXPECT_LT(c.fit.identity_edge_distance_px, 1.0);
}

TEST(DepthRegistration, ScaledAndShiftedDepthIsNotRegisteredAndTheModelIsRecovered) {
  // 7-Scenes-like: 585 px depth camera beside a 528 px colour camera, 8 px apart.
  const auto c = check_depth_registration(frames(1.10, 8, 1), kCx, kCy);
  EXPECT_FALSE(c.registered) << c.summary;
  EXPECT_NEAR(c.fit.scale, 1.10, 0.005);
  EXPECT_NEAR(c.fit.dx_px, 8.0, 1.0);
  EXPECT_NEAR(c.fit.dy_px, 1.0, 1.0);
  EXPECT_LT(c.fit.edge_distance_px, 1.0);
  EXPECT_GT(c.fit.identity_edge_distance_px, 2.0);
  EXPECT_NE(c.summary.find("NOT registered"), std::string::npos);
}

TEST(DepthRegistration, TwoFocalLengthsCountAShiftAloneDoesNot) {
  // A 5 % focal-length difference without a shift: two cameras, not registered.
  const auto scaled = check_depth_registration(frames(1.05, 0, 0), kCx, kCy);
  EXPECT_FALSE(scaled.registered) << scaled.summary;
  EXPECT_NEAR(scaled.fit.scale, 1.05, 0.005);
  // A shift alone is fitted but not acted on: texture bands beside depth edges fit such shifts on
  // registered data too (the simulator's corridor).
  const auto shifted = check_depth_registration(frames(1.0, 6, 0), kCx, kCy);
  EXPECT_TRUE(shifted.registered) << shifted.summary;
  EXPECT_NEAR(shifted.fit.dx_px, 6.0, 1.0);
}

TEST(DepthRegistration, AFlatViewGivesNoEvidenceAndCountsAsRegistered) {
  RgbdFrame wall;
  wall.rgb = cv::Mat(480, 640, CV_8UC3, cv::Scalar(100, 100, 100));
  cv::rectangle(wall.rgb, cv::Rect(100, 100, 200, 150), cv::Scalar(200, 50, 50), cv::FILLED);  // a poster
  wall.depth_m = cv::Mat(480, 640, CV_32F, cv::Scalar(2.0f));
  const auto c = check_depth_registration({wall, wall}, kCx, kCy);
  EXPECT_TRUE(c.registered);
  EXPECT_EQ(c.fit.n_edges, 0);
  EXPECT_NE(c.summary.find("too few"), std::string::npos) << c.summary;
}

TEST(DepthRegistration, EdgeDistanceIsZeroOnEdgesAndTruncatedFarFromThem) {
  // One colour edge column at u = 100; two depth edges: one on it, one 50 px away.
  EdgeFrame f;
  cv::Mat edges(480, 640, CV_8U, cv::Scalar(255));
  edges.col(100).setTo(0);
  cv::distanceTransform(edges, f.dist_colour, cv::DIST_L2, 3);
  f.depth_edges = {{100, 200}, {150, 200}};
  f.edge_z = {1.0f, 1.0f};
  EXPECT_DOUBLE_EQ(edge_distance({f}, 1, 0, 0, kCx, kCy), (0.0 + 8.0) / 2);  // 50 px truncated at 8
  // Shifting the model by +50 px in u maps the second edge onto the column, the first off it.
  EXPECT_DOUBLE_EQ(edge_distance({f}, 1, 50, 0, kCx, kCy), (8.0 + 0.0) / 2);
}

}  // namespace
}  // namespace s3m::features
