// The sensor's lies (sensor_effects.hpp): each checked against a hand computation or an ideal render
// at the instant or pose it claims to use, and all of them off by default.
#include <cmath>
#include <filesystem>
#include <fstream>
#include <string>

#include <gtest/gtest.h>
#include <unistd.h>

#include "s3m/core/config_table.hpp"
#include "s3m/core/error.hpp"
#include "s3m/io/tum_dataset.hpp"
#include "s3m/sim/sensor_effects.hpp"
#include "s3m/sim/simulate.hpp"
#include "sim_test_util.hpp"

namespace s3m::sim {
namespace {

bool same(const cv::Mat& a, const cv::Mat& b) {
  return a.size() == b.size() && a.type() == b.type() && cv::norm(a, b, cv::NORM_INF) == 0;
}

// Noise-free, unblurred 160x120 sensor: every pixel is the ideal render's.
SensorConfig exact_sensor() {
  SensorConfig s = test::small_sensor();
  s.optics_blur_px = 0;
  return s;
}

// Constant velocity in the empty room: 0.5 m/s sideways while turning at 1 rad/s about the vertical.
SE3 moving_camera(double t_s) {
  SE3 T = test::looking_along_x({2.0, 2.0 + 0.5 * t_s, 1.25});
  T.linear() = Eigen::AngleAxisd(1.0 * t_s, Vec3::UnitZ()).toRotationMatrix() * T.linear();
  return T;
}

TEST(SimSensorLies, DisparityQuantisationPutsDepthOnTheGrid) {
  // fx b = 262.5 px * 0.075 m = 19.6875 px m, steps of 1/8 px:
  // 1.2 m: d = 16.40625 px = 131.25 steps -> 131 -> 16.375 px -> z = 1.2022900763 m;
  // 2.5 m: d = 7.875 px = 63 steps exactly -> 2.5 m; 3.3 m: 47.727 steps -> 48 -> 6 px -> 3.28125 m.
  cv::Mat z = (cv::Mat_<float>(1, 4) << 1.2f, 2.5f, 3.3f, 0.0f);
  quantise_disparity(z, 262.5 * 0.075, 0.125);
  EXPECT_FLOAT_EQ(z.at<float>(0, 0), 1.2022900763f);
  EXPECT_FLOAT_EQ(z.at<float>(0, 1), 2.5f);
  EXPECT_FLOAT_EQ(z.at<float>(0, 2), 3.28125f);
  EXPECT_EQ(z.at<float>(0, 3), 0.0f);  // no depth stays no depth
  // Through the renderer (160x120: fx = 131.25 px): the wall at 3.3 m comes out at
  // 9.84375 / (round(2.98295 * 8) / 8) = 9.84375 / 3.0 = 3.28125 m.
  SensorConfig s = exact_sensor();
  s.disparity_step_px = 0.125;
  const Renderer r(test::empty_room(), s);
  const cv::Mat d = r.render(test::looking_along_x({5.0 - 3.3, 2.0, 1.25}), 1).depth_m;
  EXPECT_FLOAT_EQ(d.at<float>(60, 80), 3.28125f);
}

TEST(SimSensorLies, DepthTimeOffsetRendersDepthAtItsOwnInstant) {
  SensorConfig s = exact_sensor();
  s.depth_time_offset_s = 0.02;
  const Renderer r(test::empty_room(), s);
  const double t = 0.4, dt = s.depth_time_offset_s;
  const RgbdFrame f = r.render_timed(moving_camera, {t, t + dt}, 3);
  EXPECT_TRUE(same(f.depth_m, r.render_ideal(moving_camera(t + dt)).depth_m));
  EXPECT_TRUE(same(f.rgb, r.render_ideal(moving_camera(t)).rgb));  // colour stays at t
  const RgbdFrame synced = r.render_timed(moving_camera, {t, t}, 3);
  EXPECT_FALSE(same(f.depth_m, synced.depth_m));
  EXPECT_TRUE(same(synced.depth_m, r.render_ideal(moving_camera(t)).depth_m));
}

TEST(SimSensorLies, RollingShutterRowsSeeTheirOwnInstants) {
  SensorConfig s = exact_sensor();
  s.camera.rolling_shutter_s = 0.03;
  const Renderer r(test::empty_room(), s);
  const double t = 0.4;
  const RgbdFrame f = r.render_timed(moving_camera, {t, t}, 3);
  const IdealView first = r.render_ideal(moving_camera(t)), last = r.render_ideal(moving_camera(t + 0.03));
  const int H = f.rgb.rows;
  EXPECT_TRUE(same(f.rgb.row(0), first.rgb.row(0)));
  EXPECT_TRUE(same(f.rgb.row(H - 1), last.rgb.row(H - 1)));
  EXPECT_TRUE(same(f.labels.row(H - 1), last.labels.row(H - 1)));
  EXPECT_FALSE(same(f.rgb.row(H - 1), first.rgb.row(H - 1)));  // the camera moved meanwhile
  EXPECT_TRUE(same(f.depth_m, first.depth_m));                 // depth is a global snapshot
}

TEST(SimSensorLies, EdgeFatteningGrowsTheForegroundByN) {
  // A vertical step: columns 0-19 at 1 m (foreground), 20-39 at 3 m; one hole in the background.
  cv::Mat z(10, 40, CV_32FC1, cv::Scalar(3.0f));
  z.colRange(0, 20).setTo(1.0f);
  z.at<float>(5, 21) = 0.0f;
  for (int n : {1, 2}) {
    cv::Mat f = z.clone();
    fatten_edges(f, n, 0.04);
    EXPECT_EQ(cv::countNonZero(f.row(2) == 1.0f), 20 + n) << n;
    EXPECT_EQ(f.at<float>(2, 20 + n), 3.0f) << n;
    EXPECT_EQ(f.at<float>(5, 21), 0.0f) << n;  // a hole stays a hole
  }
  // A smooth slope (0.5 % per pixel) has no discontinuity and keeps its values.
  cv::Mat slope(5, 30, CV_32FC1);
  for (int u = 0; u < 30; ++u) slope.col(u).setTo(1.0f + 0.005f * u);
  cv::Mat kept = slope.clone();
  fatten_edges(kept, 2, 0.04);
  EXPECT_TRUE(same(kept, slope));
}

TEST(SimSensorLies, MisregistrationShiftsDepthAgainstColour) {
  // Camera 1 m from the y = 0 wall, 3 m from the back wall: the corner's column is
  // u = 79.5 + 131.25 / 3 = 123.25 (first side-wall pixel 124). Turning the depth camera by
  // atan(2 / fx) moves it by 2 (1 + (1/3)^2) = 2.2 px: first side-wall pixel 126.
  SensorConfig s = exact_sensor();
  s.depth_registration_error_px = 2.0;
  const Renderer r(test::empty_room(), s);
  const auto still = [](double) { return test::looking_along_x({2.0, 1.0, 1.25}); };
  const RgbdFrame f = r.render_timed(still, {0, 0}, 1);
  const IdealView registered = r.render_ideal(still(0));
  const auto corner = [](const cv::Mat& d) {  // the corner is a crease: the depth's slope jumps
    for (int u = 81; u < d.cols; ++u)
      if (d.at<float>(60, u - 1) - d.at<float>(60, u) > 0.02f) return u;
    return -1;
  };
  EXPECT_EQ(corner(registered.depth_m), 124);
  EXPECT_EQ(corner(f.depth_m), 126);
  EXPECT_TRUE(same(f.rgb, registered.rgb));
  // Exactly: the depth camera's view, and a point on the colour axis lands error_px right of cx.
  const SE3 T_c_d = misregistered_depth_camera(2.0, s.camera.fx);
  EXPECT_TRUE(same(f.depth_m, r.render_ideal(still(0) * T_c_d).depth_m));
  const Vec3 p_d = T_c_d.inverse() * Vec3(0, 0, 3);
  EXPECT_NEAR(s.camera.fx * p_d.x() / p_d.z(), 2.0, 1e-12);
}

TEST(SimSensorLies, EveryLieOffIsThePlainRender) {
  SensorConfig s = test::small_sensor(160, 120, true);  // noise on: the same draws, too
  const Renderer r(test::empty_room(), s);
  const SE3 T = moving_camera(0.2);
  const RgbdFrame timed = r.render_timed([&](double) { return T; }, {0.2, 0.2}, 9), plain = r.render(T, 9);
  EXPECT_TRUE(same(timed.rgb, plain.rgb));
  EXPECT_TRUE(same(timed.depth_m, plain.depth_m));
  EXPECT_TRUE(same(timed.labels, plain.labels));
}

SimConfig small_sim(std::uint64_t seed) {
  SimConfig cfg;
  cfg.seed = seed;
  cfg.sensor = test::small_sensor(160, 120, true);
  cfg.trajectory.type = "handheld";
  cfg.trajectory.frames = 12;
  return cfg;
}

TEST(SimSensorLies, DefaultsWrittenOutChangeNothing) {
  SimConfig explicit_off = small_sim(5);
  SensorConfig& s = explicit_off.sensor;
  s.depth_time_offset_s = s.time_jitter_s = s.camera.rolling_shutter_s = s.disparity_step_px = 0.0;
  s.edge_fattening_px = 0;
  s.depth_registration_error_px = 0.0;
  EXPECT_FALSE(s.timed());
  const Simulation a(small_sim(5)), b(explicit_off);
  const RgbdFrame fa = a.frame(7), fb = b.frame(7);
  EXPECT_TRUE(same(fa.rgb, fb.rgb));
  EXPECT_TRUE(same(fa.depth_m, fb.depth_m));
  EXPECT_EQ(fa.t_s, a.trajectory().samples[7].t_s);
  // The "default" profile is the built-in sensor; "ideal" only turns the noise off.
  SensorConfig d = small_sim(5).sensor;
  apply_sensor_profile("default", d);
  EXPECT_EQ(config::values(d), config::values(small_sim(5).sensor));
  apply_sensor_profile("ideal", d);
  EXPECT_FALSE(d.noise);
  EXPECT_THROW(apply_sensor_profile("kinect", d), Error);
}

TEST(SimSensorLies, RealisticProfileIsDeterministicPerSeed) {
  SimConfig cfg = small_sim(5);
  apply_sensor_profile("realistic", cfg.sensor);
  EXPECT_TRUE(cfg.sensor.timed());
  const Simulation a(cfg), b(cfg);
  cfg.seed = 6;
  const Simulation c(cfg);
  const RgbdFrame fa = a.frame(7), fb = b.frame(7), fc = c.frame(7);
  EXPECT_TRUE(same(fa.rgb, fb.rgb));
  EXPECT_TRUE(same(fa.depth_m, fb.depth_m));
  EXPECT_EQ(fa.t_s, fb.t_s);
  EXPECT_FALSE(same(fa.depth_m, fc.depth_m));
  EXPECT_NE(fa.t_s, fc.t_s);  // jitter is drawn per seed
}

TEST(SimSensorLies, StampsCarryOffsetAndJitter) {
  SimConfig cfg = small_sim(5);
  cfg.sensor.depth_time_offset_s = 0.015;
  cfg.sensor.time_jitter_s = 0.002;
  const Simulation sim(cfg);
  double prev = -1;
  for (std::size_t i = 0; i < sim.size(); ++i) {
    const FrameTimes t = sim.frame_times(i);
    const double nominal = sim.trajectory().samples[i].t_s;
    EXPECT_LE(std::abs(t.colour_s - nominal), 3 * 0.002 + 1e-12);
    EXPECT_LE(std::abs(t.depth_s - nominal - 0.015), 3 * 0.002 + 1e-12);
    EXPECT_GT(t.colour_s, prev);
    prev = t.colour_s;
    // Ground truth is the colour camera at its own stamp.
    EXPECT_TRUE(sim.T_w_c(i).isApprox(sim.trajectory().T_w_c_at(t.colour_s), 1e-12));
  }
  // Each stream's files and lists carry its own stamps.
  const auto dir = std::filesystem::temp_directory_path() / ("s3m_sim_lies_" + std::to_string(::getpid()));
  std::filesystem::remove_all(dir);
  simulate_sequence(cfg, dir.string());
  std::ifstream assoc(dir / "associations.txt");
  std::string rgb_t, rgb_file, depth_t, depth_file;
  assoc >> rgb_t >> rgb_file >> depth_t >> depth_file;
  EXPECT_EQ(rgb_t, io::tum_stamp(sim.frame_times(0).colour_s));
  EXPECT_EQ(depth_t, io::tum_stamp(sim.frame_times(0).depth_s));
  EXPECT_TRUE(std::filesystem::exists(dir / depth_file));
  std::filesystem::remove_all(dir);
}

TEST(SimSensorLies, ContinuousTrajectoryPassesThroughTheSamples) {
  const Simulation sim(small_sim(5));
  const Trajectory& tr = sim.trajectory();
  for (std::size_t i : {0u, 5u, 11u})
    EXPECT_TRUE(tr.T_w_c_at(tr.samples[i].t_s).isApprox(tr.samples[i].T_w_c, 1e-9)) << i;
  // Without the path: geodesic interpolation between the samples.
  Trajectory bare = tr;
  bare.robot_path = nullptr;
  const double mid = 0.5 * (tr.samples[3].t_s + tr.samples[4].t_s);
  EXPECT_TRUE(bare.T_w_r_at(mid).isApprox(interpolate(tr.samples[3].T_w_r, tr.samples[4].T_w_r, 0.5), 1e-9));
  EXPECT_TRUE(tr.T_w_r_at(mid).isApprox(bare.T_w_r_at(mid), 1e-3));  // a smooth path, 33 ms apart
}

TEST(SimSensorLies, ValidateNamesTheField) {
  const auto message = [](const SimConfig& c) {
    try {
      c.validate();
    } catch (const Error& e) {
      return std::string(e.what());
    }
    return std::string();
  };
  SimConfig c = small_sim(1);
  c.sensor.depth_time_offset_s = -0.02;  // depth may lead colour
  EXPECT_EQ(message(c), "");
  c.sensor.depth_time_offset_s = 0.6;
  EXPECT_NE(message(c).find("depth_time_offset_s"), std::string::npos);
  c = small_sim(1);
  c.sensor.time_jitter_s = -0.001;
  EXPECT_NE(message(c).find("time_jitter_s"), std::string::npos);
  c.sensor.time_jitter_s = 0.01;  // 6 sigma > 33 ms: stamps could swap
  EXPECT_NE(message(c).find("time_jitter_s"), std::string::npos);
  c = small_sim(1);
  c.sensor.camera.rolling_shutter_s = -0.01;
  EXPECT_NE(message(c).find("rolling_shutter_s"), std::string::npos);
  c = small_sim(1);
  c.sensor.edge_fattening_px = -1;
  EXPECT_NE(message(c).find("edge_fattening_px"), std::string::npos);
  c = small_sim(1);
  c.sensor.disparity_step_px = -0.125;
  EXPECT_NE(message(c).find("disparity_step_px"), std::string::npos);
}

}  // namespace
}  // namespace s3m::sim
