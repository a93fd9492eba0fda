// Pose graph: exact graphs stay put, a known loop correction is recovered, drift is spread.
#include <gtest/gtest.h>

#include <random>

#include "s3m/core/error.hpp"
#include "s3m/slam/optim/pose_graph.hpp"

namespace s3m::slam {
namespace {

// Ground truth: a camera flying a closed circle of radius 2 m, looking along the tangent.
std::vector<SE3> circle(int n) {
  std::vector<SE3> T_w_c;
  for (int i = 0; i < n; ++i) {
    const double a = 2.0 * M_PI * i / n;
    T_w_c.push_back(make_se3(Vec3(2.0 * std::cos(a), 2.0 * std::sin(a), 0.1 * std::sin(3 * a)),
                             Quat(Eigen::AngleAxisd(a, Vec3::UnitZ()))));
  }
  return T_w_c;
}

double max_position_error(const std::map<int, SE3>& est, const std::vector<SE3>& gt) {
  double e = 0.0;
  for (const auto& [i, T] : est) e = std::max(e, (T.translation() - gt[i].translation()).norm());
  return e;
}

TEST(PoseGraph, ConsistentGraphIsAFixedPoint) {
  const auto gt = circle(12);
  std::map<int, SE3> poses;
  std::vector<PoseGraphEdge> edges;
  for (int i = 0; i < 12; ++i) poses[i] = gt[i];
  for (int i = 0; i < 12; ++i) edges.push_back(relative_edge(i, (i + 1) % 12, gt[i], gt[(i + 1) % 12]));
  const auto r = optimize_pose_graph(poses, edges, {0});
  EXPECT_NEAR(r.initial_cost, 0.0, 1e-20);
  EXPECT_LT(max_position_error(poses, gt), 1e-9);
}

// Odometry is exact except one corrupted edge (5 deg yaw + 0.3 m) with low confidence; chaining it
// gives a drifted loop. The exact loop edge 29 -> 0 must pull every pose back to ground truth.
TEST(PoseGraph, RecoversAKnownLoopCorrection) {
  const int n = 30;
  const auto gt = circle(n);
  std::vector<PoseGraphEdge> edges;
  for (int i = 0; i + 1 < n; ++i) {
    PoseGraphEdge e = relative_edge(i, i + 1, gt[i], gt[i + 1], 100.0);
    if (i == 10) {
      e.T_from_to =
          e.T_from_to * make_se3(Vec3(0.3, 0.0, 0.0), Quat(Eigen::AngleAxisd(0.0873, Vec3::UnitZ())));
      e.information = 1e-3 * Mat6::Identity();
    }
    edges.push_back(e);
  }
  std::map<int, SE3> poses{{0, gt[0]}};
  for (int i = 0; i + 1 < n; ++i) poses[i + 1] = poses[i] * edges[i].T_from_to;
  const double drift_before = max_position_error(poses, gt);
  ASSERT_GT(drift_before, 0.5);
  edges.push_back(relative_edge(n - 1, 0, gt[n - 1], gt[0], 100.0, /*is_loop=*/true));

  const auto r = optimize_pose_graph(poses, edges, {0});
  EXPECT_TRUE(r.converged);
  EXPECT_LT(r.final_cost, 1e-3 * r.initial_cost);
  EXPECT_LT(max_position_error(poses, gt), 2e-3);  // metres; residual due to the weak edge's pull
  for (int i = 0; i < n; ++i)
    EXPECT_LT(rotation_angle_rad(poses[i].linear().transpose() * gt[i].linear()), 1e-3);
  EXPECT_TRUE(poses[0].isApprox(gt[0], 1e-12));  // the fixed node did not move
}

// Noisy, biased odometry everywhere (a realistic drifting loop): the loop edge reduces the
// trajectory error substantially even though no pose can be exact.
TEST(PoseGraph, LoopEdgeReducesDriftOfANoisyBiasedLoop) {
  const int n = 40;
  const auto gt = circle(n);
  std::mt19937 rng(7);
  std::normal_distribution<double> noise(0.0, 0.005);
  std::vector<PoseGraphEdge> edges;
  for (int i = 0; i + 1 < n; ++i) {
    PoseGraphEdge e = relative_edge(i, i + 1, gt[i], gt[i + 1], 1.0);
    const Vec3 dphi(noise(rng), noise(rng), 0.01 + noise(rng));  // 0.57 deg/step yaw bias
    e.T_from_to = e.T_from_to * make_se3(Vec3(noise(rng), noise(rng), noise(rng)), Quat(so3_exp(dphi)));
    edges.push_back(e);
  }
  std::map<int, SE3> poses{{0, gt[0]}};
  for (int i = 0; i + 1 < n; ++i) poses[i + 1] = poses[i] * edges[i].T_from_to;
  auto rmse = [&] {
    double s = 0.0;
    for (const auto& [i, T] : poses) s += (T.translation() - gt[i].translation()).squaredNorm();
    return std::sqrt(s / n);
  };
  const double before = rmse();
  edges.push_back(relative_edge(n - 1, 0, gt[n - 1], gt[0], 1.0, true));
  optimize_pose_graph(poses, edges, {0});
  const double after = rmse();
  std::printf("position RMSE before %.3f m, after %.3f m\n", before, after);
  EXPECT_GT(before, 0.3);
  EXPECT_LT(after, 0.25 * before);
}

TEST(PoseGraph, RejectsUnknownNodesAndMissingGauge) {
  std::map<int, SE3> poses{{0, SE3::Identity()}, {1, SE3::Identity()}};
  EXPECT_THROW(optimize_pose_graph(poses, {relative_edge(0, 5, SE3::Identity(), SE3::Identity())}, {0}),
               Error);
  EXPECT_THROW(optimize_pose_graph(poses, {relative_edge(0, 1, SE3::Identity(), SE3::Identity())}, {}),
               Error);
}

}  // namespace
}  // namespace s3m::slam
