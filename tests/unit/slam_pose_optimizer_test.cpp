// Pose-only optimisation recovers a known pose from noisy RGB-D / monocular correspondences with
// 30 % gross outliers, and flags the outliers.
#include <random>

#include <gtest/gtest.h>

#include "s3m/slam/optim/pose_optimizer.hpp"

namespace s3m::slam {
namespace {

PinholeCamera test_camera() {
  PinholeCamera c;
  c.fx = c.fy = 500;
  c.cx = 320;
  c.cy = 240;
  c.bf = 40;
  return c;
}

TEST(PoseOptimizer, RecoversPoseWithNoiseAndOutliers) {
  const PinholeCamera cam = test_camera();
  std::mt19937 rng(42);
  std::uniform_real_distribution<double> ux(-2, 2), uz(1, 5), uni(0, 1), big(20, 80);
  std::normal_distribution<double> px(0, 1);
  const SE3 T_c_w = se3_exp((Vec6() << 0.3, -0.1, 0.2, 0.05, -0.1, 0.03).finished());
  std::vector<PoseObservation> obs;
  std::vector<bool> is_outlier;
  while (obs.size() < 300) {
    const Vec3 p_c(ux(rng), ux(rng) * 0.75, uz(rng));
    const Eigen::Vector2d uv = cam.project(p_c);
    if (!cam.in_image(uv.x(), uv.y())) continue;
    const int level = static_cast<int>(uni(rng) * 4);
    const double sigma = std::pow(1.2, level);
    PoseObservation o;
    o.p_w = T_c_w.inverse() * p_c;
    o.inv_sigma2 = 1.0 / (sigma * sigma);
    o.uv = uv + sigma * Eigen::Vector2d(px(rng), px(rng));
    if (uni(rng) < 0.7) o.u_right = o.uv.x() - cam.bf / p_c.z() + sigma * px(rng);
    const bool outlier = obs.size() % 10 < 3;  // exactly 30 %
    if (outlier) o.uv += big(rng) * Eigen::Vector2d(uni(rng) < 0.5 ? -1 : 1, uni(rng) < 0.5 ? -1 : 1);
    obs.push_back(o);
    is_outlier.push_back(outlier);
  }
  const SE3 init = se3_exp((Vec6() << 0.05, -0.04, 0.03, 0.03, 0.02, -0.03).finished()) * T_c_w;
  const auto res = optimize_pose(obs, init, cam);
  const SE3 err = res.T_c_w * T_c_w.inverse();
  EXPECT_LT(err.translation().norm(), 0.01);
  EXPECT_LT(rotation_angle_rad(err.linear()), 0.2 * M_PI / 180);
  int caught = 0, kept = 0, n_out = 0;
  for (std::size_t i = 0; i < obs.size(); ++i) {
    n_out += is_outlier[i];
    if (is_outlier[i] && !res.inlier[i]) ++caught;
    if (!is_outlier[i] && res.inlier[i]) ++kept;
  }
  EXPECT_EQ(caught, n_out);                      // every gross outlier rejected
  EXPECT_GT(kept, 0.85 * (obs.size() - n_out));  // chi2 95 % gate keeps most inliers
  EXPECT_EQ(res.n_inliers, static_cast<int>(std::count(res.inlier.begin(), res.inlier.end(), 1)));
}

TEST(PoseOptimizer, ExactDataGivesExactPoseAndZeroChi2) {
  const PinholeCamera cam = test_camera();
  const SE3 T_c_w = se3_exp((Vec6() << -0.2, 0.1, 0.4, -0.02, 0.08, 0.1).finished());
  std::vector<PoseObservation> obs;
  for (int i = 0; i < 20; ++i) {
    const Vec3 p_c(-1.0 + 0.1 * i, 0.5 * std::sin(i), 2.0 + 0.1 * (i % 5));
    PoseObservation o;
    o.p_w = T_c_w.inverse() * p_c;
    o.uv = cam.project(p_c);
    o.u_right = (i % 2) ? o.uv.x() - cam.bf / p_c.z() : features::kNoRight;
    obs.push_back(o);
  }
  const auto res = optimize_pose(obs, se3_exp(Vec6::Constant(0.02)) * T_c_w, cam);
  EXPECT_LT((res.T_c_w.matrix() - T_c_w.matrix()).norm(), 1e-8);
  EXPECT_EQ(res.n_inliers, 20);
  double chi2 = 1;
  ASSERT_TRUE(reprojection_chi2(obs[3], res.T_c_w, cam, chi2));
  EXPECT_LT(chi2, 1e-12);
}

TEST(PoseOptimizer, PointBehindCameraIsOutlier) {
  const PinholeCamera cam = test_camera();
  PoseObservation o;
  o.p_w = Vec3(0, 0, -1);
  double chi2 = 0;
  EXPECT_FALSE(reprojection_chi2(o, SE3::Identity(), cam, chi2));
}

// The inverse-depth row (features::DepthNoiseConfig "sensor"): residual (1/z - rho) / sigma_rho, so
// a point 2 m ahead measured at rho = 1/2.1 with sigma_rho = 0.01 1/m contributes
// ((0.5 - 1/2.1) / 0.01)^2 = (2.381)^2 = 5.669 to chi2, and its pixel rows nothing.
TEST(PoseOptimizer, InverseDepthRowIsWhitenedBySigmaRho) {
  const PinholeCamera cam = test_camera();
  PoseObservation o;
  o.p_w = Vec3(0.2, -0.1, 2.0);
  o.uv = cam.project(o.p_w);
  o.u_right = o.uv.x() - cam.bf / 2.1;  // present: marks an RGB-D observation
  o.rho = 1.0 / 2.1;
  o.inv_rho_sigma2 = 1.0 / (0.01 * 0.01);
  o.inv_sigma2 = 1.0 / 1.44;  // level 1: the pixel weight must not touch the depth row
  double chi2 = 0;
  ASSERT_TRUE(reprojection_chi2(o, SE3::Identity(), cam, chi2));
  const double e = (0.5 - 1.0 / 2.1) / 0.01;
  EXPECT_NEAR(chi2, e * e, 1e-9);
  // The same observation through the virtual right coordinate: (bf/2.1 - bf/2)^2 * inv_sigma2.
  o.inv_rho_sigma2 = 0;
  ASSERT_TRUE(reprojection_chi2(o, SE3::Identity(), cam, chi2));
  const double eu = cam.bf / 2.1 - cam.bf / 2.0;
  EXPECT_NEAR(chi2, eu * eu / 1.44, 1e-9);
}

// Depth alone fixes translation along the optical axis: points straight ahead (pixel rows almost
// blind to z at the image centre) with exact inverse depths pull a 5 cm error in z back to the truth.
TEST(PoseOptimizer, InverseDepthRowsRecoverTranslationAlongTheAxis) {
  const PinholeCamera cam = test_camera();
  const SE3 T_c_w = se3_exp((Vec6() << 0.1, -0.05, 0.3, 0.01, -0.02, 0.015).finished());
  std::vector<PoseObservation> obs;
  for (int i = 0; i < 40; ++i) {
    const Vec3 p_c(0.4 * std::cos(i * 0.7), 0.3 * std::sin(i * 1.3), 1.5 + 0.05 * (i % 7));
    PoseObservation o;
    o.p_w = T_c_w.inverse() * p_c;
    o.uv = cam.project(p_c);
    o.u_right = o.uv.x() - cam.bf / p_c.z();
    o.rho = 1.0 / p_c.z();
    const double sigma_z = 0.001 + 0.0015 * p_c.z() * p_c.z();
    o.inv_rho_sigma2 = std::pow(p_c.z(), 4) / (sigma_z * sigma_z);
    obs.push_back(o);
  }
  const SE3 init = make_se3(Mat3::Identity(), Vec3(0, 0, 0.05)) * T_c_w;
  const auto res = optimize_pose(obs, init, cam);
  EXPECT_LT((res.T_c_w.matrix() - T_c_w.matrix()).norm(), 1e-8);
  EXPECT_EQ(res.n_inliers, 40);
}

}  // namespace
}  // namespace s3m::slam
