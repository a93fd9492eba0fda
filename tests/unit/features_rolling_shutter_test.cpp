// Rolling shutter: keypoints read row by row are moved to where the camera at the stamp saw them.
#include <algorithm>
#include <cmath>

#include <gtest/gtest.h>

#include "s3m/features/frame_features.hpp"

namespace s3m::features {
namespace {

PinholeCamera vga_camera() {
  PinholeCamera cam;
  cam.fx = cam.fy = 500;
  cam.cx = 320;
  cam.cy = 240;
  return cam;
}

// The camera moves with a constant twist (body frame): the camera t seconds after the stamp maps
// stamp-camera points with exp(t xi). Returns where a rolling shutter with readout_s shows p_c: the
// row v whose instant readout_s * v / (h - 1) sees the point on row v (a fixed point).
cv::Point2f seen_by_rolling_shutter(const Vec3& p_c, const Vec6& xi, double readout_s,
                                    const PinholeCamera& cam) {
  Eigen::Vector2d u = cam.project(p_c);
  for (int it = 0; it < 50; ++it) u = cam.project(se3_exp(xi * (readout_s * u.y() / (cam.height - 1))) * p_c);
  return {float(u.x()), float(u.y())};
}

struct Seen {
  std::vector<cv::KeyPoint> keypoints;
  std::vector<cv::Point2f> px;
  std::vector<float> depth_m;  // at the stamp's camera
};

Seen seen_frame(const std::vector<Vec3>& points, const Vec6& xi, double readout_s, const PinholeCamera& cam) {
  Seen f;
  for (const Vec3& p : points) {
    const cv::Point2f s = seen_by_rolling_shutter(p, xi, readout_s, cam);
    f.keypoints.emplace_back(s, 8.0f);
    f.px.push_back(s);
    f.depth_m.push_back(float(p.z()));
  }
  return f;
}

const std::vector<Vec3> kPoints = {
    {0.0, 0.0, 2.0}, {-0.6, -0.4, 1.2}, {0.5, 0.35, 0.8}, {0.9, -0.6, 3.0}, {-1.0, 0.7, 2.5}};

// 70 deg/s about y and 30 deg/s about x (a hand-held pan), plus 0.8 m/s sideways and 0.3 m/s forward.
Vec6 pan_twist(bool with_translation) {
  Vec6 xi;
  const double d = M_PI / 180.0;
  xi << (with_translation ? 0.8 : 0.0), 0.0, (with_translation ? 0.3 : 0.0), 30 * d, 70 * d, 0.0;
  return xi;  // [rho; phi] per second, se3_exp's order
}

void expect_at_stamp(const std::vector<cv::KeyPoint>& keypoints, const PinholeCamera& cam) {
  for (std::size_t i = 0; i < kPoints.size(); ++i) {
    const Eigen::Vector2d u = cam.project(kPoints[i]);
    EXPECT_NEAR(keypoints[i].pt.x, u.x(), 1e-3) << i;
    EXPECT_NEAR(keypoints[i].pt.y, u.y(), 1e-3) << i;
  }
}

TEST(RollingShutter, APureTurnIsUndoneExactlyWithoutDepth) {
  const PinholeCamera cam = vga_camera();
  const Vec6 xi = pan_twist(false);
  const double dt = 1.0 / 30, readout = 0.025;
  Seen f = seen_frame(kPoints, xi, readout, cam);
  double largest_skew_px = 0;
  for (std::size_t i = 0; i < kPoints.size(); ++i)
    largest_skew_px =
        std::max(largest_skew_px, (cam.project(kPoints[i]) - Eigen::Vector2d(f.px[i].x, f.px[i].y)).norm());
  EXPECT_GT(largest_skew_px, 10.0);  // what the correction has to undo: a 25 ms readout at 70 deg/s
  undo_rolling_shutter(f.keypoints, f.px, {}, cam, RollingShutter{readout, se3_exp(xi * dt), dt});
  expect_at_stamp(f.keypoints, cam);
}

TEST(RollingShutter, TheCamerasTranslationIsUndoneForKeypointsWithDepth) {
  const PinholeCamera cam = vga_camera();
  const Vec6 xi = pan_twist(true);
  const double dt = 1.0 / 30, readout = 0.025;
  const RollingShutter shutter{readout, se3_exp(xi * dt), dt};
  Seen f = seen_frame(kPoints, xi, readout, cam);
  Seen turned_only = f;
  undo_rolling_shutter(f.keypoints, f.px, f.depth_m, cam, shutter);
  undo_rolling_shutter(turned_only.keypoints, f.px, {}, cam, shutter);
  expect_at_stamp(f.keypoints, cam);
  double largest_translation_px = 0;
  for (std::size_t i = 0; i < kPoints.size(); ++i)
    largest_translation_px =
        std::max(largest_translation_px, double(cv::norm(turned_only.keypoints[i].pt - f.keypoints[i].pt)));
  EXPECT_GT(largest_translation_px, 2.0);  // at 0.8 m/s the translation is not negligible
}

TEST(RollingShutter, AGlobalShutterChangesNothing) {
  const PinholeCamera cam = vga_camera();
  Seen f = seen_frame(kPoints, pan_twist(true), 0.025, cam);
  const std::vector<cv::KeyPoint> before = f.keypoints;
  undo_rolling_shutter(f.keypoints, f.px, f.depth_m, cam,
                       RollingShutter{0.0, se3_exp(pan_twist(true) / 30), 1.0 / 30});
  for (std::size_t i = 0; i < before.size(); ++i) EXPECT_EQ(f.keypoints[i].pt, before[i].pt);
}

}  // namespace
}  // namespace s3m::features
