// PnP RANSAC + refinement: a known camera pose from noisy 2D-3D matches with outliers.
#include <gtest/gtest.h>

#include <random>

#include "s3m/slam/tracking/reloc_pnp.hpp"

namespace s3m::slam {
namespace {

TEST(RelocPnp, RecoversCameraPoseWithNoiseAndOutliers) {
  PinholeCamera cam;
  const SE3 T_w_c =
      make_se3(Vec3(1.0, -0.5, 0.3), Quat(Eigen::AngleAxisd(0.4, Vec3(0.2, 1, 0.1).normalized())));
  std::mt19937 rng(21);
  std::uniform_real_distribution<double> u(0, 640), v(0, 480), z(1.0, 5.0);
  std::normal_distribution<double> px_noise(0.0, 0.7);
  std::vector<Vec3> points_w;
  std::vector<Eigen::Vector2d> pixels;
  for (int i = 0; i < 150; ++i) {
    const double uu = u(rng), vv = v(rng);
    points_w.push_back(T_w_c * cam.backproject(uu, vv, z(rng)));
    // 30 % of the matches point to the wrong pixel.
    pixels.emplace_back(i % 10 < 3 ? Eigen::Vector2d(u(rng), v(rng))
                                   : Eigen::Vector2d(uu + px_noise(rng), vv + px_noise(rng)));
  }
  const auto r = solve_pnp_ransac(points_w, pixels, cam);
  ASSERT_TRUE(r.success);
  EXPECT_LT((r.T_w_c.translation() - T_w_c.translation()).norm(), 0.02);
  EXPECT_LT(rotation_angle_rad(r.T_w_c.linear().transpose() * T_w_c.linear()), 0.005);
  EXPECT_GE(r.inliers.size(), 100U);
  EXPECT_LT(r.rmse_px, 1.5);
}

TEST(RelocPnp, TooFewOrInconsistentMatchesFailWithoutThrowing) {
  PinholeCamera cam;
  std::mt19937 rng(2);
  std::uniform_real_distribution<double> u(0, 640), z(1.0, 5.0);
  std::vector<Vec3> points_w;
  std::vector<Eigen::Vector2d> pixels;
  for (int i = 0; i < 80; ++i)
    points_w.emplace_back(u(rng) / 100, u(rng) / 100, z(rng)), pixels.emplace_back(u(rng), u(rng) * 0.75);
  EXPECT_FALSE(solve_pnp_ransac(points_w, pixels, cam).success);
  EXPECT_FALSE(
      solve_pnp_ransac({points_w.begin(), points_w.begin() + 5}, {pixels.begin(), pixels.begin() + 5}, cam)
          .success);
}

}  // namespace
}  // namespace s3m::slam
