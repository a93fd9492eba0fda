// DepthOdometry (dense RGB-D odometry for the frames feature tracking loses) on the rendered room,
// where the motion between two frames is exact.
#include <cmath>
#include <cstdio>
#include <optional>
#include <vector>

#include <gtest/gtest.h>
#include <opencv2/imgproc.hpp>

#include "s3m/core/error.hpp"
#include "s3m/slam/odometry/depth_odometry.hpp"
#include "s3m/slam/odometry/keyframe_links.hpp"
#include "s3m/slam/tracking/tracker.hpp"
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
          test::render_room(test::Room{}, cam, T_w_cur, 11, 1 / 30.0, depth_noise),
          T_w_cur.inverse() * T_w_prev};
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

// KeyframeLinker: two keyframes of the room 10 UAV frames apart, the second tracked 0.3 deg / 5 mm
// off; the link measured between their images is the true relative pose, not the tracked one.
// A link that disagrees with the tracked poses by more than max_deg, or crosses sub-maps, is none.
KeyFrame room_keyframe(const SE3& T_w_c, int submap) {
  KeyFrame k;
  k.T_w_c = T_w_c;
  k.features = std::make_shared<features::FrameFeatures>();
  k.submap = submap;
  return k;
}

TEST(KeyframeLinker, MeasuresTheTrueRelativePoseOfConsecutiveKeyframes) {
  const PinholeCamera cam = test::room_camera();
  const SE3 T_w_a = test::uav_pose(20, 300), T_w_b = test::uav_pose(30, 300);
  const RgbdFrame a = test::render_room(test::Room{}, cam, T_w_a, 20, 0.0, 0.0);
  const RgbdFrame b = test::render_room(test::Room{}, cam, T_w_b, 30, 1 / 3.0, 0.0);
  const SE3 tracking_error = make_se3(so3_exp(Vec3(0.0, 0.3 * M_PI / 180, 0.0)), Vec3(0.005, 0.0, 0.0));
  const auto link_with_b_at = [&](const SE3& T_w_b_tracked, int submap_b, int queue_capacity = 0) {
    Map map;
    const KeyframeId ka = map.add_keyframe(room_keyframe(T_w_a, 0));
    const KeyframeId kb = map.add_keyframe(room_keyframe(T_w_b_tracked, submap_b));
    KeyframeLinker linker(cam, DenseLinkConfig{}, queue_capacity);
    linker.add(ka, a, map);
    linker.add(kb, b, map);
    linker.finish();
    const std::vector<KeyframeLink> links = linker.links();
    EXPECT_LE(links.size(), 1u) << "the first keyframe has nothing to link to";
    if (links.empty()) return std::optional<KeyframeLink>{};
    EXPECT_EQ(links[0].from, ka);
    EXPECT_EQ(links[0].to, kb);
    return std::optional<KeyframeLink>{links[0]};
  };
  const auto l = link_with_b_at(T_w_b * tracking_error, 0);
  ASSERT_TRUE(l.has_value());
  const SE3 err = (T_w_a.inverse() * T_w_b).inverse() * l->T_from_to;
  EXPECT_GT(angle_deg(T_w_a.inverse() * T_w_b), 2.0) << "a real motion between the keyframes";
  EXPECT_LT(angle_deg(err), 0.02);
  EXPECT_LT(err.translation().norm(), 0.001);
  EXPECT_NEAR(l->sigma_rad, DenseLinkConfig{}.sigma_deg * M_PI / 180, 1e-15);
  const SE3 far_off = make_se3(so3_exp(Vec3(0.0, 3.0 * M_PI / 180, 0.0)), Vec3::Zero());
  EXPECT_FALSE(link_with_b_at(T_w_b * far_off, 0).has_value()) << "3 deg from the tracked poses";
  EXPECT_FALSE(link_with_b_at(T_w_b, 1).has_value()) << "another sub-map";
  // On the linker's own thread: the same link, to the last bit (it starts from the poses at add()).
  const auto threaded = link_with_b_at(T_w_b * tracking_error, 0, 2);
  ASSERT_TRUE(threaded.has_value());
  EXPECT_TRUE(threaded->T_from_to.matrix() == l->T_from_to.matrix());
  EXPECT_EQ(threaded->disagreement_deg, l->disagreement_deg);
}

// A keyframe linked twice (to the one before and the one after it) is prepared once, and the
// prepared frames OpenCV has already used align exactly as fresh images do.
TEST(DepthOdometry, PreparedFramesAlignAsFreshImagesDo) {
  const PinholeCamera cam = test::room_camera();
  std::vector<RgbdFrame> f;
  for (int i : {20, 25, 30})
    f.push_back(test::render_room(test::Room{}, cam, test::uav_pose(i, 300), i, i / 30.0, 0.0));
  DepthOdometryConfig c;
  c.downsample = 1;
  const DepthOdometry odometry(cam, c);
  const DepthOdometry::PreparedFrame p0 = odometry.prepare(f[0]), p1 = odometry.prepare(f[1]),
                                     p2 = odometry.prepare(f[2]);
  // Guesses 0.3 deg / 5 mm off the truth, as tracking gives them.
  const SE3 off = make_se3(so3_exp(Vec3(0.0, 0.3 * M_PI / 180, 0.0)), Vec3(0.005, 0.0, 0.0));
  const auto truth = [](int i, int j) { return test::uav_pose(j, 300).inverse() * test::uav_pose(i, 300); };
  const SE3 g01 = off * truth(20, 25), g12 = off * truth(25, 30);
  const auto a01 = odometry.align(p0, p1, g01), a12 = odometry.align(p1, p2, g12);
  const auto b01 = odometry.align(f[0], f[1], g01), b12 = odometry.align(f[1], f[2], g12);
  ASSERT_TRUE(a01 && a12 && b01 && b12);
  EXPECT_TRUE(a01->matrix() == b01->matrix());
  EXPECT_TRUE(a12->matrix() == b12->matrix()) << "frame 1 was the destination before, now the source";
  EXPECT_LT(angle_deg(truth(25, 30).inverse() * *a12), 0.02);
  EXPECT_LT((truth(25, 30).inverse() * *a12).translation().norm(), 0.001);
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
    const auto from_truth = odometry.align(p.prev, p.cur, p.T_cur_prev),
               from_rest = odometry.align(p.prev, p.cur, SE3::Identity());
    ASSERT_TRUE(from_truth && from_rest);
    EXPECT_TRUE(
        poses_agree(*from_truth, *from_rest, t.dead_reckoning.odometry_deg, t.dead_reckoning.odometry_m));
  }
  // Facing the room's +x wall (3 m away) from 0.6 m: camera z along +x, x along -y, y along -z.
  Mat3 R;
  R.col(0) = -Vec3::UnitY();
  R.col(1) = -Vec3::UnitZ();
  R.col(2) = Vec3::UnitX();
  const SE3 T_w_prev = make_se3(R, Vec3(2.4, 0.0, 1.5)), T_w_cur = make_se3(R, Vec3(2.4, 0.03, 1.5));
  RgbdFrame prev = test::render_room(test::Room{}, cam, T_w_prev, 0, 0.0),
            cur = test::render_room(test::Room{}, cam, T_w_cur, 1, 1 / 30.0);
  prev.rgb.setTo(cv::Scalar(128, 128, 128));
  cur.rgb.setTo(cv::Scalar(128, 128, 128));
  const SE3 truth = T_w_cur.inverse() * T_w_prev;
  const auto from_truth = odometry.align(prev, cur, truth),
             from_rest = odometry.align(prev, cur, SE3::Identity());
  std::printf("plain wall: from the truth %s, from no motion %s", from_truth ? "converged" : "failed",
              from_rest ? "converged" : "failed");
  if (from_truth && from_rest)
    std::printf(", %.1f mm apart", 1000 * (*from_truth * from_rest->inverse()).translation().norm());
  std::printf("\n");
  EXPECT_FALSE(
      from_truth && from_rest &&
      poses_agree(*from_truth, *from_rest, t.dead_reckoning.odometry_deg, t.dead_reckoning.odometry_m));
}

}  // namespace
}  // namespace s3m::slam

namespace s3m::slam {
namespace {

// The room pair's view holds two walls meeting in a corner: depth alone fixes five directions, not
// the vertical slide along the corner, which stays at the guess (no motion).
TEST(DepthOdometry, ObservableAlignmentMeasuresWhatTheRoomsDepthFixes) {
  const Pair p = room_pair(0.0);
  const auto m = DepthOdometry(test::room_camera(), DepthOdometryConfig{})
                     .align_observable(p.prev, p.cur, SE3::Identity());
  ASSERT_TRUE(m.has_value());
  EXPECT_EQ(m->observed_directions, 5);
  const SE3 err = m->T_cur_prev * p.T_cur_prev.inverse();
  EXPECT_LT(angle_deg(err), 0.05);
  // What is left is a vertical slide (world z).
  const SE3 T_w_cur =
      test::uav_pose(11, 300) * make_se3(so3_exp(Vec3(0.0, -1.5 * M_PI / 180.0, 0.0)), Vec3(0.02, 0.0, 0.0));
  const Vec3 slide_w = T_w_cur.linear() * (m->T_cur_prev.inverse() * p.T_cur_prev).translation();
  std::printf("left: %.2f %.2f %.2f mm (world)\n", 1000 * slide_w.x(), 1000 * slide_w.y(),
              1000 * slide_w.z());
  EXPECT_GT(slide_w.norm(), 0.002);  // the guess was off along it and nothing in the depth says so
  EXPECT_GT(std::abs(slide_w.z()), 0.99 * slide_w.norm());
  EXPECT_LT(m->rms_m, 0.0005);  // every point back on its surface
  EXPECT_GT(m->inlier_fraction, 0.8);
}

// One plain wall head-on, the camera sliding 3 cm along it. The guess is off by what the wall
// shows (1 cm towards it, 0.5 deg of tilt) and by what it cannot (1 cm more slide, 0.3 deg about
// its normal): the first is corrected, the second kept exactly as guessed.
TEST(DepthOdometry, ObservableAlignmentCorrectsWhatOnePlaneShowsAndKeepsTheGuessForTheRest) {
  const PinholeCamera cam = test::room_camera();
  Mat3 R;  // camera z along the room's +x, x along -y, y along -z (the wall 0.6 m ahead)
  R.col(0) = -Vec3::UnitY();
  R.col(1) = -Vec3::UnitZ();
  R.col(2) = Vec3::UnitX();
  const SE3 T_w_prev = make_se3(R, Vec3(2.4, 0.0, 1.5)), T_w_cur = make_se3(R, Vec3(2.4, 0.03, 1.5));
  const RgbdFrame prev = test::render_room(test::Room{}, cam, T_w_prev, 0, 0.0);
  const RgbdFrame cur = test::render_room(test::Room{}, cam, T_w_cur, 1, 1 / 30.0);
  const SE3 truth = T_w_cur.inverse() * T_w_prev;
  const double deg = M_PI / 180.0;
  const SE3 shown = make_se3(so3_exp(Vec3(0.5 * deg, 0, 0)), Vec3(0, 0, 0.01));
  const SE3 hidden = make_se3(so3_exp(Vec3(0, 0, 0.3 * deg)), Vec3(0.01, 0, 0));
  const auto m =
      DepthOdometry(cam, DepthOdometryConfig{}).align_observable(prev, cur, hidden * shown * truth);
  ASSERT_TRUE(m.has_value());
  EXPECT_EQ(m->observed_directions, 3);
  EXPECT_LT(m->rms_m, 0.0005);
  const SE3 left = m->T_cur_prev * truth.inverse();  // what is still off: should be `hidden`
  const SE3 diff = left * hidden.inverse();
  EXPECT_LT(angle_deg(diff), 0.02);
  EXPECT_LT(diff.translation().norm(), 0.001);
}

}  // namespace
}  // namespace s3m::slam

namespace s3m::slam {
namespace {

// Session 30: a frame after a gap. OpenCV rejects an alignment that moves further than 0.15 m /
// 15 deg from its start (its defaults, made for consecutive 30 Hz frames), so a step of a 1.5 Hz
// recording could never be measured from no motion. step_scale (the gap in 30 Hz periods) widens
// that bound, and first finds the basin with the wide depth gate.
// Two rendered frames 0.67 s apart, as the TUM fr3 cabinet keyframes: 20 cm forward, 3 cm aside,
// turning 6 deg. truth: T_b_a.
struct GapPair {
  RgbdFrame a, b;
  SE3 truth;
  int periods = 20;  // 30 Hz periods between them
};
GapPair gap_pair(double depth_noise_m) {
  const PinholeCamera cam = test::room_camera();
  const int a = 40, b = 60;
  const SE3 T_w_a = test::uav_pose(a, 300);
  const SE3 T_w_b = T_w_a * make_se3(so3_exp(Vec3(0.0, 6.0 * M_PI / 180, 0.0)), Vec3(0.03, 0.0, 0.2));
  return {test::render_room(test::Room{}, cam, T_w_a, a, a / 30.0, depth_noise_m),
          test::render_room(test::Room{}, cam, T_w_b, b, b / 30.0, depth_noise_m), T_w_b.inverse() * T_w_a};
}

TEST(DepthOdometry, AStepAfterAGapIsMeasuredOnlyWithTheGapsScale) {
  const PinholeCamera cam = test::room_camera();
  const GapPair pair = gap_pair(0.002);
  const RgbdFrame &fa = pair.a, &fb = pair.b;
  const SE3 truth = pair.truth;
  ASSERT_GT(truth.translation().norm(), 0.15);
  const DepthOdometry odometry(cam, DepthOdometryConfig{});
  EXPECT_FALSE(odometry.align(fa, fb, SE3::Identity()).has_value()) << "beyond OpenCV's own bound";
  const auto T = odometry.align(fa, fb, SE3::Identity(), pair.periods);
  ASSERT_TRUE(T.has_value());
  const SE3 err = *T * truth.inverse();
  std::printf("step of %.1f deg / %.0f mm from no motion: %.3f deg / %.1f mm off\n", angle_deg(truth),
              1000 * truth.translation().norm(), angle_deg(err), 1000 * err.translation().norm());
  EXPECT_LT(angle_deg(err), 0.2);
  EXPECT_LT(err.translation().norm(), 0.005);
  // The reverse alignment, the tracker's second estimate when it has no velocity, agrees.
  const auto back = odometry.align(fb, fa, SE3::Identity(), pair.periods);
  ASSERT_TRUE(back.has_value());
  EXPECT_TRUE(poses_agree(*T, back->inverse(), TrackerConfig{}.dead_reckoning.odometry_deg,
                          TrackerConfig{}.dead_reckoning.odometry_m));
  EXPECT_THROW(odometry.align(fa, fb, SE3::Identity(), 0.5), Error) << "a scale below one period";
}

// Session 31: estimates of a step across a gap differ by a few percent of it (forward and reverse
// 0.6 deg apart on a 12 deg step of the TUM fr3 cabinet 1.34 s apart), so two of them agree within
// a fraction of the step, but within twice the bounds at most, and a 30 Hz step keeps the bounds.
TEST(DepthOdometry, StepsAgreeWithinAFractionOfTheStepUpToTwiceTheBounds) {
  const double max_deg = 0.5, max_m = 0.015, fraction = 0.1;
  auto turned = [](const SE3& T, double deg) {
    return make_se3(so3_exp(Vec3(deg * M_PI / 180, 0.0, 0.0)), Vec3::Zero()) * T;
  };
  auto moved = [](const SE3& T, double m) { return make_se3(Mat3::Identity(), Vec3(m, 0.0, 0.0)) * T; };
  // A 12 deg / 30 cm step: 10 % is 1.2 deg / 3 cm, capped at twice the bounds, 1.0 deg / 3 cm.
  const SE3 big = make_se3(so3_exp(Vec3(0.0, 12.0 * M_PI / 180, 0.0)), Vec3(0.0, 0.0, 0.3));
  EXPECT_TRUE(odometry_steps_agree(big, turned(big, 0.9), max_deg, max_m, fraction));
  EXPECT_FALSE(odometry_steps_agree(big, turned(big, 0.9), max_deg, max_m, 0.0)) << "the bounds alone";
  EXPECT_FALSE(odometry_steps_agree(big, turned(big, 1.1), max_deg, max_m, fraction))
      << "over twice the bounds";
  EXPECT_TRUE(odometry_steps_agree(big, moved(big, 0.029), max_deg, max_m, fraction));
  EXPECT_FALSE(odometry_steps_agree(big, moved(big, 0.031), max_deg, max_m, fraction));
  // A 6 deg / 20 cm step: 0.6 deg / 2 cm.
  const SE3 mid = make_se3(so3_exp(Vec3(0.0, 6.0 * M_PI / 180, 0.0)), Vec3(0.0, 0.0, 0.2));
  EXPECT_TRUE(odometry_steps_agree(mid, turned(mid, 0.55), max_deg, max_m, fraction));
  EXPECT_FALSE(odometry_steps_agree(mid, turned(mid, 0.65), max_deg, max_m, fraction));
  EXPECT_FALSE(odometry_steps_agree(mid, moved(mid, 0.021), max_deg, max_m, fraction));
  // A 30 Hz step of 1 deg / 2 cm: the bounds as they are.
  const SE3 small = make_se3(so3_exp(Vec3(0.0, 1.0 * M_PI / 180, 0.0)), Vec3(0.0, 0.0, 0.02));
  EXPECT_TRUE(odometry_steps_agree(small, turned(small, 0.45), max_deg, max_m, fraction));
  EXPECT_FALSE(odometry_steps_agree(small, turned(small, 0.55), max_deg, max_m, fraction));
  EXPECT_TRUE(odometry_steps_agree(small, moved(small, 0.014), max_deg, max_m, fraction));
  EXPECT_FALSE(odometry_steps_agree(small, moved(small, 0.016), max_deg, max_m, fraction));
}

// Session 31: after a 2 s gap forward and reverse alignment may disagree because one slid into a
// wrong basin; the depth the two views share tells them apart (TUM fr3 cabinet: right steps 0.82-0.97,
// wrong ones 0.53-0.56).
TEST(DepthOdometry, DepthAgreementIsHighForTheTrueStepOnlyAndExactOnItself) {
  const PinholeCamera cam = test::room_camera();
  const GapPair pair = gap_pair(0.0);
  const RgbdFrame &fa = pair.a, &fb = pair.b;
  // A frame onto itself: every pixel lands on itself, exactly.
  EXPECT_DOUBLE_EQ(depth_agreement(cam, fa.depth_m, fa.depth_m, SE3::Identity()), 1.0);
  const SE3 truth = pair.truth;
  const double right = depth_agreement(cam, fa.depth_m, fb.depth_m, truth);
  const SE3 turned = make_se3(so3_exp(Vec3(0.0, 20.0 * M_PI / 180, 0.0)), Vec3::Zero()) * truth;
  const double wrong = depth_agreement(cam, fa.depth_m, fb.depth_m, turned);
  std::printf("depth agreement: true step %.3f, turned 20 deg %.3f\n", right, wrong);
  EXPECT_GT(right, 0.95);
  EXPECT_LT(wrong, 0.6);
  // Nothing lands on a measured depth: 0.
  const cv::Mat none = cv::Mat::zeros(fb.depth_m.size(), CV_32FC1);
  EXPECT_EQ(depth_agreement(cam, fa.depth_m, none, truth), 0.0);
  EXPECT_THROW(depth_agreement(cam, fa.depth_m, cv::Mat::zeros(fb.depth_m.size(), CV_16UC1), truth), Error);
}

// Session 34: in the middle of the box-like room a view and the one turned 180 deg about the
// vertical see opposite walls at the same distances, so the depth of the one, not moved at all,
// lands exactly on the other's; only the walls' textures tell them apart.
TEST(DepthOdometry, ColourAgreementTellsAViewFromTheOppositeWallsWhereDepthCannot) {
  const PinholeCamera cam = test::room_camera();
  const auto at_centre = test::centre_pose;
  const RgbdFrame a = test::render_room(test::Room{}, cam, at_centre(30), 0, 0.0);
  const RgbdFrame b = test::render_room(test::Room{}, cam, at_centre(210), 1, 3.0);
  const RgbdFrame c = test::render_room(test::Room{}, cam, at_centre(40), 2, 3.0);
  const SE3 none = SE3::Identity();
  EXPECT_GT(depth_agreement(cam, a.depth_m, b.depth_m, none), 0.99) << "the two views' depth is the same";
  const std::optional<double> same = colour_agreement(cam, a, a, none);
  ASSERT_TRUE(same.has_value());
  EXPECT_NEAR(*same, 1.0, 1e-12) << "a frame onto itself: the same grey levels at the same pixels";
  const std::optional<double> opposite = colour_agreement(cam, a, b, none);
  ASSERT_TRUE(opposite.has_value());
  const SE3 T_c_a = at_centre(40).inverse() * at_centre(30);
  const std::optional<double> right = colour_agreement(cam, a, c, T_c_a);
  ASSERT_TRUE(right.has_value());
  std::printf("colour agreement: true 10 deg step %.3f, opposite walls as no motion %.3f\n", *right,
              *opposite);
  EXPECT_GT(*right, 0.95);
  EXPECT_LT(*opposite, 0.2);
  // The grey levels inverted: perfectly anti-correlated. A black image has no contrast to judge.
  RgbdFrame inverted = a;
  inverted.rgb = cv::Mat(cv::Scalar::all(255) - a.rgb);  // a new image: a's is shared, not copied
  EXPECT_NEAR(*colour_agreement(cam, a, inverted, none), -1.0, 1e-12);
  RgbdFrame black = a;
  black.rgb = cv::Mat::zeros(a.rgb.size(), a.rgb.type());
  EXPECT_FALSE(colour_agreement(cam, a, black, none).has_value());
  // Nothing seen by both (no depth in the current frame): nothing to judge.
  RgbdFrame no_depth = c;
  no_depth.depth_m = cv::Mat::zeros(c.depth_m.size(), CV_32FC1);
  EXPECT_FALSE(colour_agreement(cam, a, no_depth, T_c_a).has_value());
  RgbdFrame wrong_type = c;
  wrong_type.depth_m = cv::Mat::zeros(c.depth_m.size(), CV_16UC1);
  EXPECT_THROW(colour_agreement(cam, a, wrong_type, T_c_a), Error);
  RgbdFrame half_colour = c;
  cv::resize(c.rgb, half_colour.rgb, cv::Size(), 0.5, 0.5);
  EXPECT_THROW(colour_agreement(cam, a, half_colour, T_c_a), Error) << "colour and depth of different sizes";
}

}  // namespace
}  // namespace s3m::slam
