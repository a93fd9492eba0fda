// 3D-3D RANSAC: recovers a known SE3 from RGB-D-like correspondences with noise and outliers.
#include <gtest/gtest.h>

#include <random>

#include "s3m/slam/loop/loop_geometry.hpp"

namespace s3m::slam {
namespace {

TEST(LoopGeometry, FitSe3IsExactOnNoiseFreePoints) {
  const SE3 T = make_se3(Vec3(0.4, -1.2, 0.3), Quat(Eigen::AngleAxisd(0.7, Vec3(1, 2, 3).normalized())));
  std::vector<Vec3> a, b{{0, 0, 1}, {1, 0, 2}, {0, 1, 3}, {1, 1, 1.5}};
  for (const auto& p : b) a.push_back(T * p);
  EXPECT_TRUE(fit_se3(a, b, {0, 1, 2, 3}).isApprox(T, 1e-9));
}

TEST(LoopGeometry, RansacRecoversPoseWith40PercentOutliers) {
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> xy(-1.5, 1.5), z(0.8, 4.0), far(-3.0, 3.0);
  std::normal_distribution<double> noise(0.0, 0.005);
  const SE3 T_a_b = make_se3(Vec3(0.25, 0.05, -0.4), Quat(Eigen::AngleAxisd(0.35, Vec3::UnitY())));
  std::vector<Vec3> a, b;
  std::vector<bool> is_outlier;
  for (int i = 0; i < 200; ++i) {
    const Vec3 p_b(xy(rng), xy(rng), z(rng));
    b.push_back(p_b);
    const bool outlier = i % 5 < 2;
    is_outlier.push_back(outlier);
    a.push_back(outlier ? Vec3(far(rng), far(rng), z(rng))
                        : Vec3(T_a_b * p_b + Vec3(noise(rng), noise(rng), noise(rng))));
  }
  const auto r = estimate_se3_ransac(a, b);
  ASSERT_TRUE(r.success);
  EXPECT_LT((r.T_a_b.translation() - T_a_b.translation()).norm(), 0.005);
  EXPECT_LT(rotation_angle_rad(r.T_a_b.linear().transpose() * T_a_b.linear()), 0.003);
  EXPECT_LT(r.rmse_m, 0.015);
  int wrong = 0;
  for (int i : r.inliers) wrong += is_outlier[size_t(i)];
  EXPECT_LE(wrong, 2);  // a random outlier may fall inside the 3-11 cm gate by chance
  EXPECT_GE(r.inliers.size(), 115U);
}

TEST(LoopGeometry, RandomCorrespondencesAreRejected) {
  std::mt19937 rng(4);
  std::uniform_real_distribution<double> u(-2.0, 2.0), z(0.8, 4.0);
  std::vector<Vec3> a, b;
  for (int i = 0; i < 60; ++i) a.emplace_back(u(rng), u(rng), z(rng)), b.emplace_back(u(rng), u(rng), z(rng));
  EXPECT_FALSE(estimate_se3_ransac(a, b).success);
}

}  // namespace
}  // namespace s3m::slam
