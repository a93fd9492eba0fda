// io::DepthToColour: depth from a camera beside the colour camera, in the colour camera's pixels.
// Expected values by hand: a shift of fx * baseline / z pixels, patches that cover finer pixels, the
// nearer surface winning, the occlusion shadow left empty.
#include <cmath>
#include <string>
#include <vector>

#include <gtest/gtest.h>
#include <opencv2/calib3d.hpp>

#include "s3m/core/error.hpp"
#include "s3m/io/depth_to_colour.hpp"

namespace s3m::io {
namespace {

PinholeCamera camera(double f, double cx, double cy, int w, int h) {
  PinholeCamera c;
  c.fx = c.fy = f, c.cx = cx, c.cy = cy, c.width = w, c.height = h;
  return c;
}

SE3 shift_x(double x_m) {
  SE3 T = SE3::Identity();
  T.translation() = Vec3(x_m, 0, 0);
  return T;
}

TEST(IoDepthToColour, SameCameraIsTheIdentity) {
  const PinholeCamera c = camera(100, 19.5, 14.5, 40, 30);
  cv::Mat depth(30, 40, CV_32FC1);
  cv::randu(depth, 0.5, 4.0);
  depth.at<float>(3, 4) = 0.0f;
  depth.at<float>(5, 6) = std::nanf("");
  const cv::Mat out = DepthToColour(c, c, SE3::Identity())(depth);
  depth.at<float>(5, 6) = 0.0f;  // non-finite = no measurement
  EXPECT_EQ(cv::countNonZero(out != depth), 0);
}

TEST(IoDepthToColour, BaselineShiftsByFocalTimesBaselineOverDepth) {
  const PinholeCamera c = camera(100, 19.5, 14.5, 40, 30);
  const cv::Mat plane(30, 40, CV_32FC1, cv::Scalar(2.0f));
  // p_c = p_d + (0.1, 0, 0): u_c = u_d + 100 * 0.1 / 2 = u_d + 5.
  const cv::Mat out = DepthToColour(c, c, shift_x(0.1))(plane);
  for (int v = 0; v < 30; ++v)
    for (int u = 0; u < 40; ++u) EXPECT_FLOAT_EQ(out.at<float>(v, u), u < 5 ? 0.0f : 2.0f) << u << "," << v;
}

TEST(IoDepthToColour, FinerColourImageHasNoHolesBetweenDepthSamples) {
  // Colour twice as fine over the same field of view: each depth pixel covers 2x2 colour pixels.
  const PinholeCamera d = camera(100, 19.5, 14.5, 40, 30), c = camera(200, 39.5, 29.5, 80, 60);
  cv::Mat depth(30, 40, CV_32FC1, cv::Scalar(2.0f));
  depth.at<float>(10, 10) = 1.5f;
  const cv::Mat out = DepthToColour(d, c, SE3::Identity())(depth);
  EXPECT_EQ(cv::countNonZero(out), 80 * 60);
  for (int v : {20, 21})
    for (int u : {20, 21}) EXPECT_FLOAT_EQ(out.at<float>(v, u), 1.5f);
  EXPECT_FLOAT_EQ(out.at<float>(19, 20), 2.0f);
  EXPECT_FLOAT_EQ(out.at<float>(22, 21), 2.0f);
}

TEST(IoDepthToColour, NearerSurfaceWinsAndTheShadowStaysEmpty) {
  const PinholeCamera c = camera(100, 19.5, 14.5, 40, 30);
  cv::Mat depth(30, 40, CV_32FC1, cv::Scalar(3.0f));
  depth(cv::Rect(10, 0, 5, 30)) = 1.0f;  // a pole at 1 m in front of a wall at 3 m
  const cv::Mat out = DepthToColour(c, c, shift_x(0.1))(depth);
  // Pole: 100 * 0.1 / 1 = 10 px -> colour 20..24, over the wall (shifted 3.33 px) that lands there too.
  // Wall: depth 9 -> [8.5, 9.5] + 3.33 -> colour 12; depth 15 -> colour 18. Colour 13..17 is wall
  // the depth camera could not see behind the pole.
  for (int u = 12; u <= 25; ++u) {
    const float expected = u >= 20 && u <= 24 ? 1.0f : (u >= 13 && u <= 17 ? 0.0f : 3.0f);
    EXPECT_FLOAT_EQ(out.at<float>(15, u), expected) << "colour column " << u;
  }
}

TEST(IoDepthToColour, ColourDistortionIsOpenCvsForwardModel) {
  const PinholeCamera d = camera(100, 19.5, 14.5, 40, 30);
  PinholeCamera c = d;
  c.dist = {-2.0, 0.0, 0.01, 0.0, 0.0};  // strong barrel distortion
  cv::Mat depth(30, 40, CV_32FC1, cv::Scalar(0.0f));
  depth.at<float>(29, 39) = 2.0f;  // one sample near a corner, where distortion moves it most
  const cv::Mat out = DepthToColour(d, c, SE3::Identity())(depth);
  std::vector<cv::Point2d> projected;
  const std::vector<cv::Point3d> p{{(39 - 19.5) / 100.0 * 2, (29 - 14.5) / 100.0 * 2, 2.0}};
  cv::projectPoints(p, cv::Vec3d(0, 0, 0), cv::Vec3d(0, 0, 0), cv::Matx33d(100, 0, 19.5, 0, 100, 14.5, 0, 0, 1),
                    std::vector<double>(c.dist.begin(), c.dist.end()), projected);
  ASSERT_LT(projected[0].x, 39.5);
  ASSERT_LT(projected[0].y, 29.5);
  EXPECT_GT(std::abs(projected[0].x - 39), 1.0);  // the distortion is not negligible here
  EXPECT_FLOAT_EQ(out.at<float>(static_cast<int>(std::lround(projected[0].y)), static_cast<int>(std::lround(projected[0].x))),
                  2.0f);
  EXPECT_EQ(out.at<float>(29, 39), 0.0f);
  EXPECT_EQ(cv::countNonZero(out), 1);
}

TEST(IoDepthToColour, PointsFarOutsideTheViewDoNotFoldBackOrOverflow) {
  // A very wide depth camera (x, y up to +-1) beside a colour camera with strong barrel distortion
  // (k1 -2: x (1 - 2 r^2) turns back beyond r = 0.41, so a point at r = 0.55 would land inside the
  // image's corners). The ring beyond r = 0.45 is at 1 m, nearer than the 2 m inside: any of it
  // drawn into the image would win there.
  const PinholeCamera wide = camera(20, 19.5, 14.5, 40, 30);
  PinholeCamera c = camera(100, 19.5, 14.5, 40, 30);
  c.dist = {-2.0, 0.0, 0.0, 0.0, 0.0};
  cv::Mat depth(30, 40, CV_32FC1);
  for (int v = 0; v < 30; ++v)
    for (int u = 0; u < 40; ++u) {
      const double x = (u - 19.5) / 20, y = (v - 14.5) / 20;
      depth.at<float>(v, u) = x * x + y * y > 0.45 * 0.45 ? 1.0f : 2.0f;
    }
  depth.at<float>(0, 0) = 1e-7f;  // a near point the baseline throws 1e8 px away: skipped, no int overflow
  SE3 T = SE3::Identity();
  T.translation() = Vec3(0.1, 0, 0);
  PinholeCamera plain = c;
  plain.dist = {0, 0, 0, 0, 0};
  for (const PinholeCamera& colour : {c, plain})
    for (const SE3& T_c_d : {SE3(SE3::Identity()), T}) {
      const cv::Mat out = DepthToColour(wide, colour, T_c_d)(depth);
      EXPECT_EQ(cv::countNonZero(out == 1.0f), 0);
      EXPECT_GT(cv::countNonZero(out == 2.0f), 0);
    }
}

TEST(IoDepthToColour, WrongDepthImageSizeIsNamed) {
  const PinholeCamera d = camera(100, 19.5, 14.5, 40, 30);
  try {
    DepthToColour(d, d, SE3::Identity())(cv::Mat(30, 41, CV_32FC1, cv::Scalar(1.0f)));
    FAIL() << "a 41x30 depth image was accepted for a 40x30 depth camera";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("41x30 (expected CV_32FC1 40x30"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace s3m::io
