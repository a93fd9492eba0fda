#include "s3m/slam/optim/pose_graph.hpp"

#include <ceres/ceres.h>

#include <memory>

#include "s3m/core/error.hpp"

namespace s3m::slam {

namespace {

// Residual of one relative-pose edge, as in Ceres' pose_graph_3d example:
// [p_ab_est - p_ab_meas; 2 vec(q_ab_meas^-1 q_ab_est)], whitened by sqrt(information).
struct RelativePoseError {
  RelativePoseError(const SE3& T_a_b, const Mat6& sqrt_information)
      : p_ab(T_a_b.translation()), q_ab(Quat(T_a_b.linear())), sqrt_info(sqrt_information) {}

  template <typename T>
  bool operator()(const T* p_a_ptr, const T* q_a_ptr, const T* p_b_ptr, const T* q_b_ptr,
                  T* residual_ptr) const {
    Eigen::Map<const Eigen::Matrix<T, 3, 1>> p_a(p_a_ptr), p_b(p_b_ptr);
    Eigen::Map<const Eigen::Quaternion<T>> q_a(q_a_ptr), q_b(q_b_ptr);
    const Eigen::Quaternion<T> q_a_inv = q_a.conjugate();
    const Eigen::Quaternion<T> q_ab_est = q_a_inv * q_b;
    const Eigen::Matrix<T, 3, 1> p_ab_est = q_a_inv * (p_b - p_a);
    const Eigen::Quaternion<T> dq = q_ab.template cast<T>().conjugate() * q_ab_est;
    Eigen::Map<Eigen::Matrix<T, 6, 1>> r(residual_ptr);
    r.template head<3>() = p_ab_est - p_ab.template cast<T>();
    r.template tail<3>() = T(2.0) * dq.vec();
    r.applyOnTheLeft(sqrt_info.template cast<T>());
    return true;
  }

  Vec3 p_ab;
  Quat q_ab;
  Mat6 sqrt_info;
};

Mat6 matrix_sqrt(const Mat6& information) {
  // Upper Cholesky factor U with U^T U = information, so |U r|^2 = r^T information r.
  Eigen::LLT<Mat6> llt(information);
  require(llt.info() == Eigen::Success, "pose graph: edge information must be symmetric positive definite");
  return llt.matrixU();
}

}  // namespace

PoseGraphEdge relative_edge(int from, int to, const SE3& T_w_from, const SE3& T_w_to, double weight,
                            bool is_loop) {
  PoseGraphEdge e;
  e.from = from;
  e.to = to;
  e.T_from_to = T_w_from.inverse() * T_w_to;
  e.information = weight * Mat6::Identity();
  e.is_loop = is_loop;
  return e;
}

void PoseGraphConfig::validate() const {
  require(max_iterations >= 1, "PoseGraphConfig.max_iterations must be >= 1");
  require(loop_huber >= 0.0, "PoseGraphConfig.loop_huber must be >= 0");
}

PoseGraphResult optimize_pose_graph(std::map<int, SE3>& T_w_nodes, const std::vector<PoseGraphEdge>& edges,
                                    const std::set<int>& fixed, const PoseGraphConfig& config) {
  config.validate();
  require(!fixed.empty(), "optimize_pose_graph: at least one node must be fixed");
  // 1. Parameter blocks: position [m] and quaternion (x, y, z, w as Eigen stores it) per node.
  struct Block {
    Vec3 p;
    Quat q;
  };
  std::map<int, Block> blocks;
  for (const auto& [id, T] : T_w_nodes) blocks[id] = {T.translation(), Quat(T.linear()).normalized()};

  // 2. One residual per edge.
  ceres::Problem problem;
  for (const PoseGraphEdge& e : edges) {
    auto a = blocks.find(e.from), b = blocks.find(e.to);
    if (a == blocks.end() || b == blocks.end()) {
      throw Error("optimize_pose_graph: edge " + std::to_string(e.from) + " -> " + std::to_string(e.to) +
                  " names a node without a pose");
    }
    auto* cost = new ceres::AutoDiffCostFunction<RelativePoseError, 6, 3, 4, 3, 4>(
        new RelativePoseError(e.T_from_to, matrix_sqrt(e.information)));
    ceres::LossFunction* loss =
        (e.is_loop && config.loop_huber > 0.0) ? new ceres::HuberLoss(config.loop_huber) : nullptr;
    problem.AddResidualBlock(cost, loss, a->second.p.data(), a->second.q.coeffs().data(), b->second.p.data(),
                             b->second.q.coeffs().data());
  }

  // 3. Quaternions live on the unit sphere; fixed nodes are constant.
  for (auto& [id, blk] : blocks) {
    if (!problem.HasParameterBlock(blk.p.data())) continue;  // isolated node: nothing to optimise
    problem.SetManifold(blk.q.coeffs().data(), new ceres::EigenQuaternionManifold);
    if (fixed.count(id)) {
      problem.SetParameterBlockConstant(blk.p.data());
      problem.SetParameterBlockConstant(blk.q.coeffs().data());
    }
  }

  // 4. Solve. Pose graphs are sparse and banded plus a few loop edges: sparse Cholesky fits.
  ceres::Solver::Options options;
  options.linear_solver_type = ceres::SPARSE_NORMAL_CHOLESKY;
  options.max_num_iterations = config.max_iterations;
  options.num_threads = 1;
  ceres::Solver::Summary summary;
  ceres::Solve(options, &problem, &summary);

  // 5. Write back.
  for (const auto& [id, blk] : blocks) T_w_nodes[id] = make_se3(blk.p, blk.q);
  return {summary.initial_cost, summary.final_cost, int(summary.iterations.size()),
          summary.termination_type == ceres::CONVERGENCE};
}

}  // namespace s3m::slam
