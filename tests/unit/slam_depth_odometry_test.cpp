// DepthOdometry (dense RGB-D odometry for the frames feature tracking loses) on the rendered room,
// where the motion between two frames is exact.
#include <cmath>
#include <cstdio>

#include <gtest/gtest.h>

#include "s3m/core/error.hpp"
#include "s3m/slam/depth_odometry.hpp"
#include "s3m/slam/tracker.hpp"
#include "slam_synthetic_room.hpp"

namespace s3m::slam {
namespace {

double angle_deg(const SE3& T) { return rotation_angle_rad(T.linear()) * 180.0 / M_PI; }

// Two views of the room one UAV frame apart, plus a 1.5 deg / 2 cm kick so the motion is not tiny.
struct Pair {
  RgbdFrame prev, cur;
  SE3 T_cur_prev;
};
Pair room_pair(double depth_noise) {
  const PinholeCamera cam = test::room_camera();
  const SE3 T_w_prev = test::uav_pose(10, 300);
  const SE3 kick = make_se3(so3_exp(Vec3(0.0, -1.5 * M_PI / 180.0, 0.0)), Vec3(0.02, 0.0, 0.0));
  const SE3 T_w_cur = test::uav_pose(11, 300) * kick;
  return {test::render_room(test::Room{}, cam, T_w_prev, 10, 0.0, depth_noise),
          test::render_room(test::Room{}, cam, T_w_cur, 11, 1 / 30.0, depth_noise), T_w_cur.inverse() * T_w_prev};
}

TEST(DepthOdometry, RecoversTheExactMotionFromNoMotionGuess) {
  const Pair p = room_pair(0.0);
  const DepthOdometry odometry(test::room_camera(), DepthOdometryConfig{});
  const auto T = odometry.align(p.prev, p.cur, SE3::Identity());
  ASSERT_TRUE(T.has_value());
  const SE3 err = *T * p.T_cur_prev.inverse();
  EXPECT_GT(angle_deg(p.T_cur_prev), 1.5);  // a real motion to find
  EXPECT_LT(angle_deg(err), 0.05);
  EXPECT_LT(err.translation().norm(), 0.002);
}

TEST(DepthOdometry, DepthNoiseCostsLittleAtFullResolution) {
  const Pair p = room_pair(0.003);  // 0.3 % of the range, as a structured-light sensor at 1-2 m
  DepthOdometryConfig c;
  c.downsample = 1;
  const auto T = DepthOdometry(test::room_camera(), c).align(p.prev, p.cur, SE3::Identity());
  ASSERT_TRUE(T.has_value());
  const SE3 err = *T * p.T_cur_prev.inverse();
  EXPECT_LT(angle_deg(err), 0.1);
  EXPECT_LT(err.translation().norm(), 0.003);
}

TEST(DepthOdometry, RejectsBadConfigAndMismatchedImages) {
  DepthOdometryConfig c;
  c.downsample = 0;
  EXPECT_THROW(DepthOdometry(test::room_camera(), c), Error);
  c = DepthOdometryConfig{};
  c.max_depth_m = c.min_depth_m;
  EXPECT_THROW(c.validate(), Error);
  Pair p = room_pair(0.0);
  p.cur.depth_m = cv::Mat();
  try {
    DepthOdometry(test::room_camera(), DepthOdometryConfig{}).align(p.prev, p.cur, SE3::Identity());
    FAIL() << "no error";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("frame 11"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace s3m::slam

namespace s3m::slam {
namespace {

// The tracker's second opinion on a measured motion: the same alignment from no motion. On the
// textured room both starts land on the same motion; a plain grey wall seen head-on, the camera
// sliding 3 cm along it, leaves the slide unobservable, and the two starts do not agree.
TEST(DepthOdometry, TwoStartsAgreeOnAWellConditionedPairOnly) {
  const PinholeCamera cam = test::room_camera();
  const DepthOdometry odometry(cam, DepthOdometryConfig{});
  const TrackerConfig t;
  {
    const Pair p = room_pair(0.0);
    const auto from_truth = odometry.align(p.prev, p.cur, p.T_cur_prev), from_rest = odometry.align(p.prev, p.cur, SE3::Identity());
    ASSERT_TRUE(from_truth && from_rest);
    EXPECT_TRUE(poses_agree(*from_truth, *from_rest, t.odometry_deg, t.odometry_m));
  }
  // Facing the room's +x wall (3 m away) from 0.6 m: camera z along +x, x along -y, y along -z.
  Mat3 R;
  R.col(0) = -Vec3::UnitY();
  R.col(1) = -Vec3::UnitZ();
  R.col(2) = Vec3::UnitX();
  const SE3 T_w_prev = make_se3(R, Vec3(2.4, 0.0, 1.5)), T_w_cur = make_se3(R, Vec3(2.4, 0.03, 1.5));
  RgbdFrame prev = test::render_room(test::Room{}, cam, T_w_prev, 0, 0.0), cur = test::render_room(test::Room{}, cam, T_w_cur, 1, 1 / 30.0);
  prev.rgb.setTo(cv::Scalar(128, 128, 128));
  cur.rgb.setTo(cv::Scalar(128, 128, 128));
  const SE3 truth = T_w_cur.inverse() * T_w_prev;
  const auto from_truth = odometry.align(prev, cur, truth), from_rest = odometry.align(prev, cur, SE3::Identity());
  std::printf("plain wall: from the truth %s, from no motion %s", from_truth ? "converged" : "failed",
              from_rest ? "converged" : "failed");
  if (from_truth && from_rest)
    std::printf(", %.1f mm apart", 1000 * (*from_truth * from_rest->inverse()).translation().norm());
  std::printf("\n");
  EXPECT_FALSE(from_truth && from_rest && poses_agree(*from_truth, *from_rest, t.odometry_deg, t.odometry_m));
}

}  // namespace
}  // namespace s3m::slam
