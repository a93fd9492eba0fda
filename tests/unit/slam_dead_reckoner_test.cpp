// DeadReckoner (the poses of frames feature tracking loses) on rendered frame pairs of the test
// room, where the motion between two frames is exact.
#include <cmath>
#include <optional>

#include <gtest/gtest.h>

#include "s3m/core/error.hpp"
#include "s3m/slam/tracking/dead_reckoner.hpp"
#include "slam_synthetic_room.hpp"

namespace s3m::slam {
namespace {

double angle_deg(const SE3& T) { return rotation_angle_rad(T.linear()) * 180.0 / M_PI; }
SE3 yaw(double deg) { return make_se3(so3_exp(Vec3(0.0, deg * M_PI / 180.0, 0.0)), Vec3::Zero()); }

// Two views of the room one UAV frame apart, plus a 1.5 deg / 2 cm kick so the motion is not tiny.
struct Pair {
  RgbdFrame last, cur;
  SE3 T_c_w_last, T_c_w_cur, T_cur_last;
};
Pair room_pair() {
  const PinholeCamera cam = test::room_camera();
  const SE3 T_w_last = test::uav_pose(10, 300);
  const SE3 kick = make_se3(so3_exp(Vec3(0.0, -1.5 * M_PI / 180.0, 0.0)), Vec3(0.02, 0.0, 0.0));
  const SE3 T_w_cur = test::uav_pose(11, 300) * kick;
  return {test::render_room(test::Room{}, cam, T_w_last, 10, 0.0),
          test::render_room(test::Room{}, cam, T_w_cur, 11, 1 / 30.0), T_w_last.inverse(), T_w_cur.inverse(),
          T_w_cur.inverse() * T_w_last};
}

void expect_near(const SE3& T, const SE3& truth, double deg, double m) {
  const SE3 err = T * truth.inverse();
  EXPECT_LT(angle_deg(err), deg);
  EXPECT_LT(err.translation().norm(), m);
}

TEST(DeadReckoner, MeasuresThePairsMotionFromAPredictionOffByMoreThanTheBounds) {
  const Pair p = room_pair();
  const DeadReckoner dr(test::room_camera(), DeadReckonerConfig{});
  // 1 deg off: the alignment from the prediction does not agree with it, the one from no motion does.
  const std::optional<SE3> T = dr.measure(p.last, p.cur, yaw(1.0) * p.T_cur_last);
  ASSERT_TRUE(T.has_value());
  EXPECT_GT(angle_deg(p.T_cur_last), 1.5);
  expect_near(*T, p.T_cur_last, 0.05, 0.002);
}

TEST(DeadReckoner, MeasuresFromRestConfirmedByTheReverseAlignment) {
  const Pair p = room_pair();
  const DeadReckoner dr(test::room_camera(), DeadReckonerConfig{});
  const std::optional<SE3> T = dr.measure_from_rest(p.last, p.cur);
  ASSERT_TRUE(T.has_value());
  expect_near(*T, p.T_cur_last, 0.05, 0.002);
}

// The room is symmetric about its centre: turned round, the camera sees the same depth on walls of
// another texture. Depth alone confirms "no motion" both ways; the colour images refuse it.
TEST(DeadReckoner, ColourRefusesTheViewTurnedRoundThatDepthConfirms) {
  const PinholeCamera cam = test::room_camera();
  const RgbdFrame a = test::render_room(test::Room{}, cam, test::centre_pose(0), 0, 0.0);
  const RgbdFrame b = test::render_room(test::Room{}, cam, test::centre_pose(180), 1, 1 / 30.0);
  DeadReckonerConfig no_colour;
  no_colour.odometry_min_colour_agreement = -1;
  const std::optional<SE3> depth_only = DeadReckoner(cam, no_colour).measure_from_rest(a, b);
  ASSERT_TRUE(depth_only.has_value());
  EXPECT_LT(angle_deg(*depth_only), 1.0);  // "no motion", 180 deg from the truth
  EXPECT_FALSE(DeadReckoner(cam, DeadReckonerConfig{}).measure_from_rest(a, b).has_value());
}

TEST(DeadReckoner, CoastsOnTheVelocityForCoastFramesWithoutImages) {
  DeadReckonerConfig c;
  c.coast_frames = 3;
  DeadReckoner dr(test::room_camera(), c);
  const SE3 v = make_se3(so3_exp(Vec3(0.0, 0.01, 0.0)), Vec3(0.01, 0.0, 0.0));
  dr.start_coasting(v);
  SE3 T_c_w = test::uav_pose(0, 300).inverse();
  RgbdFrame blank;
  for (int i = 1; i <= 3; ++i) {
    blank.index = i;
    const auto r = dr.reckon(blank, /*from_rest=*/false, T_c_w);
    ASSERT_TRUE(r.has_value()) << "frame " << i;
    EXPECT_FALSE(r->measured);
    EXPECT_TRUE(r->T_c_w.isApprox(v * T_c_w, 0.0));  // exactly the velocity's prediction
    T_c_w = r->T_c_w;
    dr.end_lost_frame(true);
  }
  blank.index = 4;
  EXPECT_FALSE(dr.reckon(blank, false, T_c_w).has_value());  // coasting is over
}

TEST(DeadReckoner, NoVelocityAndNotFromRestGivesNoPose) {
  DeadReckoner dr(test::room_camera(), DeadReckonerConfig{});
  const Pair p = room_pair();
  dr.keep(p.last, p.T_c_w_last);
  dr.start_coasting(std::nullopt);
  EXPECT_FALSE(dr.reckon(p.cur, /*from_rest=*/false, p.T_c_w_last).has_value());
  const auto r = dr.reckon(p.cur, /*from_rest=*/true, p.T_c_w_last);
  ASSERT_TRUE(r.has_value());
  EXPECT_TRUE(r->measured);
  expect_near(r->T_c_w, p.T_c_w_cur, 0.05, 0.002);
}

TEST(DeadReckoner, ReckonsALostFrameFromTheKeptImagesAndLearnsTheVelocity) {
  const Pair p = room_pair();
  DeadReckoner dr(test::room_camera(), DeadReckonerConfig{});
  dr.keep(p.last, p.T_c_w_last);
  dr.start_coasting(yaw(0.2) * p.T_cur_last);  // the velocity, slightly off
  // The last pose the tracker had is a poor guess; the measurement starts from the kept frame's.
  const auto r = dr.reckon(p.cur, false, yaw(5.0) * p.T_c_w_last);
  ASSERT_TRUE(r.has_value());
  EXPECT_TRUE(r->measured);
  expect_near(r->T_c_w, p.T_c_w_cur, 0.05, 0.002);
  ASSERT_TRUE(dr.velocity().has_value());
  expect_near(*dr.velocity(), p.T_cur_last, 0.05, 0.002);
}

TEST(DeadReckoner, DoesNotMeasureATurnWiderThanTheFieldOfViewOrWhenOff) {
  const Pair p = room_pair();
  for (const bool off : {false, true}) {
    DeadReckonerConfig c;
    if (off) c.odometry_frames = 0;
    DeadReckoner dr(test::room_camera(), c);
    dr.keep(p.last, p.T_c_w_last);
    const SE3 v = off ? p.T_cur_last : yaw(80.0);  // 80 deg a frame: the views share nothing
    dr.start_coasting(v);
    const auto r = dr.reckon(p.cur, false, p.T_c_w_last);
    ASSERT_TRUE(r.has_value());
    EXPECT_FALSE(r->measured) << (off ? "odometry_frames 0" : "80 deg turn");
    EXPECT_TRUE(r->T_c_w.isApprox(v * p.T_c_w_last, 0.0));
  }
}

TEST(DeadReckoner, ConfigRejectsNegativeBoundsNamingTheKey) {
  DeadReckonerConfig c;
  c.odometry_min_colour_agreement = 2;
  try {
    c.validate();
    FAIL() << "accepted odometry_min_colour_agreement 2";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("odometry_min_colour_agreement"), std::string::npos);
  }
  c = DeadReckonerConfig{};
  c.coast_frames = -1;
  EXPECT_THROW(c.validate(), Error);
}

}  // namespace
}  // namespace s3m::slam
