#include <gtest/gtest.h>

#include <random>

#include "s3m/core/se3.hpp"

using namespace s3m;

namespace {
SE3 random_pose(std::mt19937& rng) {
  std::normal_distribution<double> n(0, 1);
  Vec6 xi;
  for (int i = 0; i < 6; ++i) xi[i] = n(rng);
  return se3_exp(xi);
}
}  // namespace

TEST(Se3, ExpLogRoundTrip) {
  std::mt19937 rng(42);
  for (int i = 0; i < 200; ++i) {
    std::normal_distribution<double> n(0, 0.8);
    Vec6 xi;
    for (int k = 0; k < 6; ++k) xi[k] = n(rng);
    if (xi.tail<3>().norm() > 3.0) continue;  // log is unique only for angles < pi
    EXPECT_LT((se3_log(se3_exp(xi)) - xi).norm(), 1e-9);
  }
}

TEST(Se3, QuaternionRoundTrip) {
  std::mt19937 rng(1);
  for (int i = 0; i < 100; ++i) {
    const SE3 T = random_pose(rng);
    const Quat q(T.linear());
    const SE3 T2 = make_se3(T.translation(), q);
    EXPECT_LT((T.matrix() - T2.matrix()).norm(), 1e-12);
  }
}

TEST(Se3, CompositionFollowsFrameNames) {
  // T_w_r = T_w_c * T_c_r : a point at the robot origin lands where the calibration puts it.
  const SE3 T_w_c = make_se3(Vec3(1, 2, 3), Quat(Eigen::AngleAxisd(M_PI / 2, Vec3::UnitZ())));
  const SE3 T_c_r = make_se3(Vec3(0.1, 0, 0), Quat::Identity());
  const SE3 T_w_r = T_w_c * T_c_r;
  // Robot origin in camera frame is (0.1,0,0); rotated 90 deg about z gives (0,0.1,0) + (1,2,3).
  EXPECT_LT((T_w_r.translation() - Vec3(1, 2.1, 3)).norm(), 1e-12);
}

TEST(Se3, KnownExpValues) {
  Vec6 xi = Vec6::Zero();
  xi[5] = M_PI / 2;  // 90 deg about z, no translation
  const SE3 T = se3_exp(xi);
  EXPECT_NEAR((T * Vec3(1, 0, 0) - Vec3(0, 1, 0)).norm(), 0, 1e-12);
  EXPECT_NEAR(rotation_angle_rad(T.linear()), M_PI / 2, 1e-12);
}

// a = d * b with d a 2 deg turn and a 5 cm step: they agree within (2 deg, 5 cm) and not within
// less of either, in both orders. b sits 3 m from the origin, turned 60 deg: a^-1 * b would move
// 14.7 cm (the step expressed in b's frame), so this pins the a * b^-1 definition.
TEST(Se3, PosesAgreeComparesTheTransformBetweenThem) {
  const SE3 d = make_se3(Vec3(0.03, 0.04, 0.0), Quat(Eigen::AngleAxisd(2.0 * M_PI / 180.0, Vec3::UnitZ())));
  const SE3 b = make_se3(Vec3(3.0, 0.0, 0.0), Quat(Eigen::AngleAxisd(M_PI / 3.0, Vec3::UnitY())));
  const SE3 a = d * b;
  EXPECT_TRUE(poses_agree(a, b, 2.0 + 1e-9, 0.05 + 1e-9));
  EXPECT_TRUE(poses_agree(b, a, 2.0 + 1e-9, 0.05 + 1e-9));
  EXPECT_FALSE(poses_agree(a, b, 2.0 - 1e-6, 1.0));
  EXPECT_FALSE(poses_agree(a, b, 10.0, 0.05 - 1e-6));
  EXPECT_FALSE(poses_agree(b, a, 10.0, 0.05 - 1e-6));
  EXPECT_GT((a.inverse() * b).translation().norm(), 0.1);
  EXPECT_TRUE(poses_agree(b, b, 1e-6, 1e-12));
}

TEST(Se3, OrthonormalizeFixesDrift) {
  SE3 T = make_se3(Vec3(1, 0, 0), Quat(Eigen::AngleAxisd(0.3, Vec3::UnitX())));
  T.linear()(0, 1) += 1e-4;
  const SE3 Tn = orthonormalized(T);
  EXPECT_LT((Tn.linear() * Tn.linear().transpose() - Mat3::Identity()).norm(), 1e-12);
  EXPECT_NEAR(Tn.linear().determinant(), 1.0, 1e-12);
}

TEST(Se3, InterpolateEndpointsAndMidpoint) {
  const SE3 A = make_se3(Vec3(0, 0, 0), Quat::Identity());
  const SE3 B = make_se3(Vec3(2, 0, 0), Quat(Eigen::AngleAxisd(1.0, Vec3::UnitY())));
  EXPECT_LT((interpolate(A, B, 0).matrix() - A.matrix()).norm(), 1e-12);
  EXPECT_LT((interpolate(A, B, 1).matrix() - B.matrix()).norm(), 1e-12);
  const SE3 M = interpolate(A, B, 0.5);
  EXPECT_NEAR(M.translation().x(), 1.0, 1e-12);
  EXPECT_NEAR(rotation_angle_rad(M.linear()), 0.5, 1e-12);
}

TEST(Se3, WeightedMeanOfNearbyPoses) {
  // About one axis the mean angle is the weighted mean of the angles: (1 x 0.3 + 2 x 0.6) / 3 = 0.5;
  // the translation (1 x (0, 0, 0) + 2 x (3, 0, 6)) / 3 = (2, 0, 4).
  const Vec3 z = Vec3(1, 2, 2).normalized();
  const SE3 A = make_se3(Vec3(0, 0, 0), Quat(Eigen::AngleAxisd(0.3, z)));
  const SE3 B = make_se3(Vec3(3, 0, 6), Quat(Eigen::AngleAxisd(0.6, z)));
  const SE3 M = weighted_mean({{A, 1.0}, {B, 2.0}});
  EXPECT_LT((M.translation() - Vec3(2, 0, 4)).norm(), 1e-12);
  const Eigen::AngleAxisd aa(M.linear());
  EXPECT_NEAR(aa.angle(), 0.5, 1e-12);
  EXPECT_LT((aa.axis() - z).norm(), 1e-9);
  // One pose, or the same pose twice: itself.
  EXPECT_LT((weighted_mean({{B, 0.7}}).matrix() - B.matrix()).norm(), 1e-12);
  EXPECT_LT((weighted_mean({{B, 1.0}, {B, 5.0}}).matrix() - B.matrix()).norm(), 1e-12);
  // Order does not matter beyond rounding, for poses a few degrees apart about different axes.
  const SE3 C = make_se3(Vec3(1, 1, 1), Quat(Eigen::AngleAxisd(0.05, Vec3::UnitX())));
  const SE3 D = make_se3(Vec3(1, 1, 2), Quat(Eigen::AngleAxisd(0.04, Vec3::UnitY())));
  const SE3 CD = weighted_mean({{C, 1.0}, {D, 3.0}}), DC = weighted_mean({{D, 3.0}, {C, 1.0}});
  EXPECT_LT(rotation_angle_rad(CD.linear().transpose() * DC.linear()), 1e-4);
  EXPECT_NEAR(CD.translation().z(), 1.75, 1e-12);
  EXPECT_THROW(weighted_mean({}), std::exception);
  EXPECT_THROW(weighted_mean({{A, 0.0}}), std::exception);
}

TEST(Se3, PowerComposesAndInverts) {
  // A screw motion: 10 deg about z and 3 cm along x per step.
  Vec6 xi;
  xi << 0.03, 0.0, 0.0, 0.0, 0.0, 10.0 * M_PI / 180.0;
  const SE3 T = se3_exp(xi);
  EXPECT_EQ(se3_power(T, 1.0).matrix(), T.matrix());  // bit for bit
  EXPECT_LT((se3_power(T, 2.0).matrix() - (T * T).matrix()).norm(), 1e-12);
  EXPECT_LT((se3_power(T, -1.0).matrix() - T.inverse().matrix()).norm(), 1e-12);
  const SE3 half = se3_power(T, 0.5);
  EXPECT_LT(((half * half).matrix() - T.matrix()).norm(), 1e-12);
  EXPECT_NEAR(rotation_angle_rad(half.linear()), 5.0 * M_PI / 180.0, 1e-12);
  EXPECT_LT((se3_power(T, 0.0).matrix() - SE3::Identity().matrix()).norm(), 1e-15);
}
