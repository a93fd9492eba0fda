// Trajectories: smooth, within speed limits, clear of furniture, camera/robot frames consistent.
#include <gtest/gtest.h>

#include "s3m/core/error.hpp"
#include "s3m/sim/renderer.hpp"
#include "s3m/sim/trajectory.hpp"
#include "sim_test_util.hpp"

namespace s3m::sim {
namespace {

TEST(SimTrajectory, DefaultMountLooksForwardAndDown) {
  // Camera 12 deg pitched down, 10 cm ahead and 3 cm below the robot centre.
  const SE3 T_r_c = camera_to_robot(CameraMount{}).inverse();
  const Vec3 z_c_in_r = T_r_c.linear().col(2), x_c_in_r = T_r_c.linear().col(0);
  const double a = 12.0 * M_PI / 180.0;
  EXPECT_TRUE(z_c_in_r.isApprox(Vec3(std::cos(a), 0, -std::sin(a)), 1e-12));
  EXPECT_TRUE(x_c_in_r.isApprox(Vec3(0, -1, 0), 1e-12));  // image right = robot right = -y
  EXPECT_TRUE(T_r_c.translation().isApprox(Vec3(0.10, 0, -0.03), 1e-12));
}

TEST(SimTrajectory, AllPresetsAndTypesAreSafeSmoothAndConsistent) {
  for (const auto& preset : scene_presets()) {
    const Scene scene = make_scene(preset, 7);
    for (const auto& type : trajectory_types()) {
      TrajectoryConfig cfg;
      cfg.type = type;
      SCOPED_TRACE(preset + "/" + type);
      Trajectory t;
      ASSERT_NO_THROW(t = make_trajectory(scene, cfg, 7));  // throws when too close to furniture
      ASSERT_EQ(t.samples.size(), 300u);
      EXPECT_LE(t.max_speed_mps(), 1.5 + 1e-6);
      EXPECT_GT(t.length_m(), type == "hover" ? 0.0 : 2.0);
      for (std::size_t i = 0; i < t.samples.size(); ++i) {
        const auto& s = t.samples[i];
        ASSERT_TRUE(s.T_w_c.isApprox(s.T_w_r * t.T_c_r.inverse(), 1e-12));
        ASSERT_TRUE(scene.room.contains(s.T_w_c.translation(), 0.1));
        if (i == 0) continue;
        const auto& p = t.samples[i - 1];
        EXPECT_NEAR(s.t_s - p.t_s, 1.0 / 30.0, 1e-9);
        // Smooth and trackable: at most 6 cm and 3.5 deg between frames at 30 Hz (the panning
        // hand: 5.5 deg, 165 deg/s at the peak of its sweep).
        const double max_deg = type == "handheld_pan" ? 5.5 : 3.5;
        ASSERT_LE((s.T_w_c.translation() - p.T_w_c.translation()).norm(), 0.06) << i;
        ASSERT_LE(rotation_angle_rad(p.T_w_c.linear().transpose() * s.T_w_c.linear()), max_deg * M_PI / 180.0)
            << i;
      }
    }
  }
}

TEST(SimTrajectory, UavTiltFollowsAcceleration) {
  // Hovering gives a level body; in the forward-flight phase the body pitches into the motion.
  const Scene scene = make_scene("office", 7);
  TrajectoryConfig cfg;
  cfg.type = "hover";
  const Trajectory hover = make_trajectory(scene, cfg, 7);
  for (const auto& s : hover.samples) EXPECT_GT(s.T_w_r.linear()(2, 2), std::cos(1.0 * M_PI / 180.0));
  cfg.type = "forward";
  const Trajectory fwd = make_trajectory(scene, cfg, 7);
  double max_tilt = 0;
  for (const auto& s : fwd.samples)
    max_tilt = std::max(max_tilt, std::acos(std::min(1.0, s.T_w_r.linear()(2, 2))));
  EXPECT_GT(max_tilt, 0.5 * M_PI / 180.0);
  EXPECT_LT(max_tilt, 15.0 * M_PI / 180.0);
}

TEST(SimTrajectory, LoopRevisitsTheStart) {
  TrajectoryConfig cfg;
  cfg.type = "loop";
  const Trajectory t = make_trajectory(make_scene("office", 7), cfg, 7);
  const SE3& start = t.samples.front().T_w_c;
  double best_dist = 1e9, best_rot = 0;
  for (std::size_t i = t.samples.size() / 2; i < t.samples.size(); ++i) {
    const double d = (t.samples[i].T_w_c.translation() - start.translation()).norm();
    if (d < best_dist) {
      best_dist = d;
      best_rot = rotation_angle_rad(start.linear().transpose() * t.samples[i].T_w_c.linear());
    }
  }
  EXPECT_LT(best_dist, 0.1);
  EXPECT_LT(best_rot, 8.0 * M_PI / 180.0);  // attitude differs by the UAV's tilt at speed
}

TEST(SimTrajectory, UavSweepTakesOffAndTurnsAFullCircle) {
  const Scene scene = make_scene("office", 7);
  const Trajectory t = make_trajectory(scene, TrajectoryConfig{}, 7);
  EXPECT_NEAR(t.samples.front().T_w_r.translation().z(), scene.flight_zone.min.z(), 1e-9);
  EXPECT_GT(t.samples[60].T_w_r.translation().z(), 1.2);
  // Accumulate the heading change of the robot's x axis: at least one full turn.
  double turned = 0;
  for (std::size_t i = 1; i < t.samples.size(); ++i) {
    const Vec3 a = t.samples[i - 1].T_w_r.linear().col(0), b = t.samples[i].T_w_r.linear().col(0);
    turned += std::abs(std::atan2(a.x() * b.y() - a.y() * b.x(), a.x() * b.x() + a.y() * b.y()));
  }
  EXPECT_GT(turned, 2 * M_PI);
}

TEST(SimTrajectory, ViewsShowContentNotBlankWalls) {
  // Every 25th frame of every preset/type: no single class covers > 92% of the image.
  for (const auto& preset : scene_presets()) {
    const Scene scene = make_scene(preset, 7);
    const Renderer r(scene, test::small_sensor(80, 60));
    for (const auto& type : trajectory_types()) {
      TrajectoryConfig cfg;
      cfg.type = type;
      const Trajectory t = make_trajectory(scene, cfg, 7);
      for (std::size_t i = 0; i < t.samples.size(); i += 25) {
        const IdealView v = r.render_ideal(t.samples[i].T_w_c);
        int hist[cls::kCount] = {};
        for (int y = 0; y < v.labels.rows; ++y)
          for (int x = 0; x < v.labels.cols; ++x) hist[v.labels.at<std::uint16_t>(y, x)]++;
        const int biggest = *std::max_element(hist, hist + cls::kCount);
        EXPECT_LT(biggest, 0.92 * 80 * 60) << preset << "/" << type << " frame " << i;
      }
    }
  }
}

TEST(SimTrajectory, RejectsUnknownTypeAndBadFrames) {
  TrajectoryConfig cfg;
  cfg.type = "teleport";
  EXPECT_THROW(make_trajectory(make_scene("office", 1), cfg, 1), Error);
  cfg.type = "loop";
  cfg.frames = 0;
  EXPECT_THROW(make_trajectory(make_scene("office", 1), cfg, 1), Error);
  EXPECT_THROW(make_scene("castle", 1), Error);
}

}  // namespace
}  // namespace s3m::sim
