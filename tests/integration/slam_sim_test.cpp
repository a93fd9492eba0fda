// End to end: RGB-D SLAM on the simulator's 300-frame office UAV flight (fixed seed) against its
// ground truth. ATE after SE3 alignment (TUM definition) and every frame tracked; the robot
// trajectory uses the simulated camera mount as T_c_r.
#include <cmath>

#include <gtest/gtest.h>

#include "s3m/eval/align.hpp"
#include "s3m/sim/simulate.hpp"
#include "s3m/slam/system.hpp"

namespace s3m {
namespace {

struct FlightResult {
  int lost = 0;
  double ate_cam = 0, ate_robot = 0;
  double sim3_scale = 0;  // scale of the sim3 alignment of the camera positions onto the truth
};

sim::SimConfig flight(const std::string& scene, const std::string& type, bool noise = true) {
  sim::SimConfig sc;  // 300 frames, seed 7
  sc.scene = scene;
  sc.trajectory.type = type;
  sc.trajectory.frames = 300;
  sc.sensor.noise = noise;
  return sc;
}

FlightResult fly(const sim::SimConfig& sc) {
  const std::string& type = sc.trajectory.type;
  const sim::Simulation sim(sc);
  slam::SlamConfig cfg;
  cfg.T_c_r = sim.trajectory().T_c_r;
  slam::System slam(sim.camera(), cfg);
  int lost = 0;
  for (std::size_t i = 0; i < sim.size(); ++i) {
    const auto r = slam.track(sim.frame(i));
    lost += r.state != slam::TrackState::kOk;
  }
  slam.finish();
  FlightResult res;
  res.lost = lost;
  const auto cam = slam.camera_trajectory();
  const auto rob = slam.robot_trajectory();
  EXPECT_EQ(cam.size(), sim.size());
  std::vector<Vec3> est, gt, est_r, gt_r;
  for (std::size_t k = 0; k < cam.size(); ++k) {
    const auto& s = sim.trajectory().samples[cam[k].frame_index];
    est.push_back(cam[k].T_w_x.translation());
    gt.push_back(s.T_w_c.translation());
    est_r.push_back(rob[k].T_w_x.translation());
    gt_r.push_back(s.T_w_r.translation());
  }
  auto ate = [](const std::vector<Vec3>& e, const std::vector<Vec3>& g) {
    const auto A = eval::align_positions(e, g, eval::AlignMode::kSe3);
    double s = 0;
    for (std::size_t i = 0; i < e.size(); ++i) s += (A.apply(e[i]) - g[i]).squaredNorm();
    return std::sqrt(s / e.size());
  };
  res.ate_cam = ate(est, gt);
  res.ate_robot = ate(est_r, gt_r);
  res.sim3_scale = eval::align_positions(est, gt, eval::AlignMode::kSim3).scale;
  std::printf("%s %s%s: lost %d, ATE camera %.4f m, robot %.4f m, sim3 scale %.4f, keyframes %d\n", sc.scene.c_str(),
              type.c_str(), sc.sensor.noise ? "" : " (no noise)", lost, res.ate_cam, res.ate_robot, res.sim3_scale,
              slam.map().n_keyframes());
  return res;
}

TEST(SlamOnSimulator, OfficeFigure8UavFlight300FramesAteBelow2cm) {
  const FlightResult r = fly(flight("office", "figure8"));
  EXPECT_EQ(r.lost, 0);
  EXPECT_LT(r.ate_cam, 0.02);
  EXPECT_LT(r.ate_robot, 0.02);
}

// Issue 20: on exact depth the motion is neither shrunk nor stretched. With ORB-SLAM's virtual
// right coordinate the depth row weighed like ~10 cm at 2 m and local BA shrank such flights by
// 1-3 % (scale 0.976-0.990); the sensor depth model (features.depth_noise) keeps it within 0.1 %.
TEST(SlamOnSimulator, NoiseFreeCorridorLawnmowerHasExactScaleAndAteBelow5mm) {
  const FlightResult r = fly(flight("corridor", "lawnmower", /*noise=*/false));
  EXPECT_EQ(r.lost, 0);
  EXPECT_LT(r.ate_cam, 0.005);
  EXPECT_NEAR(r.sim3_scale, 1.0, 0.002);
}

}  // namespace
}  // namespace s3m
