// Sensor model statistics, and geometric consistency between ground-truth poses and rendered views.
#include <cmath>

#include <gtest/gtest.h>

#include "s3m/sim/simulate.hpp"
#include "sim_test_util.hpp"

namespace s3m::sim {
namespace {

// Flat wall straight ahead at z_m; only Gaussian noise enabled.
cv::Mat noisy_wall_depth(double z_m, SensorConfig s, std::uint64_t seed) {
  s.noise = true;
  s.edge_dropout = s.dark_dropout = s.random_dropout = 0.0;
  const Renderer r(test::empty_room(), s);
  return r.render(test::looking_along_x({5.0 - z_m, 2.0, 1.25}), seed).depth_m;
}

TEST(SimSensor, DepthNoiseHasTheConfiguredSigma) {
  SensorConfig s = test::small_sensor(320, 240);
  for (double z : {1.0, 2.5, 4.0}) {
    const cv::Mat d = noisy_wall_depth(z, s, 11);
    // Only rows that see the wall (hand-computed from the geometry, as in the render test).
    double sum = 0, sum2 = 0;
    int n = 0;
    const double f = s.camera.fy, cx = s.camera.cx, cy = s.camera.cy;
    for (int y = 0; y < d.rows; ++y) {
      if (std::abs(y - cy) / f * z > 1.2) continue;  // floor or ceiling
      for (int x = 0; x < d.cols; ++x) {
        if (std::abs(x - cx) / f * z > 1.9) continue;  // side walls
        const double e = d.at<float>(y, x) - z;
        sum += e;
        sum2 += e * e;
        ++n;
      }
    }
    ASSERT_GT(n, 10000);
    const double mean = sum / n, sd = std::sqrt(sum2 / n - mean * mean), sigma = s.depth_sigma_m(z);
    EXPECT_NEAR(sd, sigma, 0.03 * sigma) << "z = " << z;
    EXPECT_NEAR(mean, 0.0, 5.0 * sigma / std::sqrt(n)) << "z = " << z;
  }
  EXPECT_NEAR(s.depth_sigma_m(4.0), 0.001 + 0.0015 * 16.0, 1e-12);
}

TEST(SimSensor, DropoutRateAndRangeLimits) {
  SensorConfig s = test::small_sensor(320, 240);
  s.noise = true;
  s.edge_dropout = s.dark_dropout = 0.0;
  s.random_dropout = 0.1;
  const Renderer r(test::empty_room(), s);
  const cv::Mat d = r.render(test::looking_along_x({3.0, 2.0, 1.25}), 5).depth_m;
  const double missing = 1.0 - static_cast<double>(cv::countNonZero(d)) / d.total();
  EXPECT_NEAR(missing, 0.1, 0.005);  // 76800 Bernoulli(0.1) draws: sd 0.0011
  s.random_dropout = 0.0;
  s.max_depth_m = 2.5;  // the wall at 3 m is beyond range
  const Renderer far(test::empty_room(), s);
  const cv::Mat d2 = far.render(test::looking_along_x({2.0, 2.0, 1.25}), 5).depth_m;
  EXPECT_EQ(d2.at<float>(120, 160), 0.0f);
  s.max_depth_m = 8.0;
  s.min_depth_m = 3.5;  // and too close
  const Renderer near(test::empty_room(), s);
  EXPECT_EQ(near.render(test::looking_along_x({2.0, 2.0, 1.25}), 5).depth_m.at<float>(120, 160), 0.0f);
}

TEST(SimSensor, EdgesAndDarkSurfacesLoseDepth) {
  SimConfig cfg;
  cfg.sensor = test::small_sensor(320, 240, true);
  cfg.sensor.random_dropout = 0.0;
  cfg.trajectory.frames = 20;
  const Simulation sim(cfg);
  int edge_total = 0, edge_missing = 0, flat_total = 0, flat_missing = 0;
  for (int i : {5, 15}) {
    const IdealView v = sim.renderer().render_ideal(sim.trajectory().samples[i].T_w_c);
    const cv::Mat d = sim.frame(i).depth_m;
    for (int y = 1; y + 1 < d.rows; ++y)
      for (int x = 1; x + 1 < d.cols; ++x) {
        const float z = v.depth_m.at<float>(y, x);
        const bool edge = std::abs(v.depth_m.at<float>(y, x + 1) - z) > 0.1f * z ||
                          std::abs(v.depth_m.at<float>(y + 1, x) - z) > 0.1f * z;
        const bool plain = v.albedo_lum.at<float>(y, x) > 0.1f && v.cos_incidence.at<float>(y, x) > 0.3f;
        const bool missing = d.at<float>(y, x) == 0.0f;
        if (edge) edge_total++, edge_missing += missing;
        else if (plain) flat_total++, flat_missing += missing;
      }
  }
  ASSERT_GT(edge_total, 100);
  EXPECT_GT(static_cast<double>(edge_missing) / edge_total, 0.3);
  EXPECT_LT(static_cast<double>(flat_missing) / flat_total, 0.02);
}

// Re-project frame A's depth into frame B with the ground-truth relative pose.
struct Agreement {
  int compared = 0, agreeing = 0;
};
Agreement reproject(const Simulation& sim, int a, int b, double tol_rel, const SE3& error = SE3::Identity()) {
  const PinholeCamera& cam = sim.camera();
  const cv::Mat da = sim.frame(a).depth_m, db = sim.frame(b).depth_m;
  const SE3 T_b_a = error * sim.trajectory().samples[b].T_w_c.inverse() * sim.trajectory().samples[a].T_w_c;
  Agreement r;
  for (int y = 0; y < cam.height; y += 2)
    for (int x = 0; x < cam.width; x += 2) {
      const float z = da.at<float>(y, x);
      if (z <= 0) continue;
      const Vec3 p_b = T_b_a * cam.backproject(x, y, z);
      if (p_b.z() <= 0.1) continue;
      const Eigen::Vector2d uv = cam.project(p_b);
      const int u = static_cast<int>(std::lround(uv.x())), v = static_cast<int>(std::lround(uv.y()));
      if (!cam.in_image(u, v)) continue;
      const float zb = db.at<float>(v, u);
      if (zb <= 0) continue;
      ++r.compared;
      r.agreeing += std::abs(zb - p_b.z()) < tol_rel * p_b.z();
    }
  return r;
}

TEST(SimSensor, GroundTruthPosesMatchRenderedViews) {
  SimConfig cfg;
  cfg.sensor = test::small_sensor(320, 240, false);
  cfg.trajectory.type = "figure8";
  const Simulation exact(cfg);
  // Noise-free: nearest-pixel lookup only errs at depth edges and on steep surfaces.
  const Agreement e = reproject(exact, 100, 104, 0.01);
  ASSERT_GT(e.compared, 5000);
  EXPECT_GT(static_cast<double>(e.agreeing) / e.compared, 0.95);
  // A wrong pose (10 cm off) must be caught by the same check.
  SE3 off = SE3::Identity();
  off.translation() = Vec3(0.1, 0.0, 0.0);
  const Agreement w = reproject(exact, 100, 104, 0.01, off);
  EXPECT_LT(static_cast<double>(w.agreeing) / w.compared, 0.5);
  cfg.sensor.noise = true;
  const Simulation noisy(cfg);
  const Agreement n = reproject(noisy, 100, 104, 0.03);  // ~3 sigma at 4 m plus lookup error
  EXPECT_GT(static_cast<double>(n.agreeing) / n.compared, 0.9);
}

}  // namespace
}  // namespace s3m::sim
