#pragma once
// Pose-graph optimisation over SE3 keyframe poses (the essential graph of ORB-SLAM, in SE3 because
// RGB-D fixes the scale): relative-pose edges weighted by an information matrix, solved with Ceres
// on position + unit quaternion (EigenQuaternionManifold).
#include <map>
#include <set>
#include <vector>

#include <Eigen/Core>

#include "s3m/core/se3.hpp"

namespace s3m::slam {

using Mat6 = Eigen::Matrix<double, 6, 6>;

struct PoseGraphEdge {
  int from = -1;  // node ids (keyframe ids)
  int to = -1;
  // Measured relative pose T_from_to = T_w_from^-1 * T_w_to (maps `to` camera points into `from`).
  SE3 T_from_to = SE3::Identity();
  // Information (inverse covariance) of the residual [translation (m); rotation (rad)].
  Mat6 information = Mat6::Identity();
  bool is_loop = false;
};

// An edge whose measurement is the current relative pose of two nodes (spanning-tree and
// covisibility edges keep the local shape the tracker measured while the loop edge pulls).
PoseGraphEdge relative_edge(int from, int to, const SE3& T_w_from, const SE3& T_w_to, double weight = 1.0,
                            bool is_loop = false);

struct PoseGraphConfig {
  int max_iterations = 30;
  // Huber scale on loop edges' whitened residual (0 = plain least squares); limits the damage of
  // a wrong loop that slipped through verification.
  double loop_huber = 0.0;
  void validate() const;
};

struct PoseGraphResult {
  double initial_cost = 0.0;  // Ceres cost (0.5 * sum of squared whitened residuals)
  double final_cost = 0.0;
  int iterations = 0;
  bool converged = false;
};

// Optimises the camera-to-world poses T_w_node in place. Nodes in `fixed` (at least one, usually
// the first keyframe) stay put, which removes the gauge freedom. Throws s3m::Error when an edge
// names an unknown node or nothing is fixed.
PoseGraphResult optimize_pose_graph(std::map<int, SE3>& T_w_nodes, const std::vector<PoseGraphEdge>& edges,
                                    const std::set<int>& fixed, const PoseGraphConfig& config = {});

}  // namespace s3m::slam
