#include "s3m/slam/optim/bundle_adjustment.hpp"

#include <algorithm>
#include <cmath>
#include <map>
#include <set>

#include <ceres/ceres.h>
#include <ceres/rotation.h>

#include "s3m/core/error.hpp"
#include "s3m/slam/optim/keypoint_measurement.hpp"

namespace s3m::slam {
namespace {

// Reprojection residual of a point into a frame whose pose is [q (w,x,y,z) world-to-camera, t].
// Rows: u, v and, for RGB-D observations, DepthRow's depth row.
template <int kRows>
struct ReprojectionCost {
  ReprojectionCost(const BaObservation& o, const PinholeCamera& c)
      : u(o.uv.x()),
        v(o.uv.y()),
        w(std::sqrt(o.inv_sigma2)),
        fx(c.fx),
        fy(c.fy),
        cx(c.cx),
        cy(c.cy),
        bf(c.bf),
        depth(o) {}

  template <typename T>
  bool operator()(const T* q, const T* t, const T* p_w, T* r) const {
    T p[3];
    ceres::UnitQuaternionRotatePoint(q, p_w, p);
    p[0] += t[0];
    p[1] += t[1];
    p[2] += t[2];
    const T iz = T(1.0) / p[2];
    const T pu = fx * p[0] * iz + cx;
    r[0] = w * (pu - u);
    r[1] = w * (fy * p[1] * iz + cy - v);
    if constexpr (kRows == 3) r[2] = depth.residual(pu, iz, bf);
    return true;
  }
  double u, v, w, fx, fy, cx, cy, bf;
  DepthRow depth;
};

// Error of a measured relative pose T_from_to given both frames' world-to-camera poses:
// T_from_to(est) = T_c_w[from] * T_c_w[to]^-1; rows: the rotation of meas^-1 * est as an angle-axis
// vector over sigma_rad, its translation over sigma_m.
struct PoseLinkCost {
  explicit PoseLinkCost(const BaPoseLink& l)
      : t_meas(l.T_from_to.translation()), w_r(1 / l.sigma_rad), w_t(1 / l.sigma_m) {
    const Quat q(l.T_from_to.linear());
    q_meas_inv[0] = q.w(), q_meas_inv[1] = -q.x(), q_meas_inv[2] = -q.y(), q_meas_inv[3] = -q.z();
  }
  template <typename T>
  bool operator()(const T* q_f, const T* t_f, const T* q_t, const T* t_t, T* r) const {
    // R_est = R_f R_t^T, t_est = t_f - R_est t_t.
    const T q_t_inv[4] = {q_t[0], -q_t[1], -q_t[2], -q_t[3]};
    T q_est[4], rt[3], q_err[4];
    ceres::QuaternionProduct(q_f, q_t_inv, q_est);
    ceres::UnitQuaternionRotatePoint(q_est, t_t, rt);
    const T t_est[3] = {t_f[0] - rt[0], t_f[1] - rt[1], t_f[2] - rt[2]};
    const T qm[4] = {T(q_meas_inv[0]), T(q_meas_inv[1]), T(q_meas_inv[2]), T(q_meas_inv[3])};
    ceres::QuaternionProduct(qm, q_est, q_err);
    ceres::QuaternionToAngleAxis(q_err, r);
    const T dt[3] = {t_est[0] - T(t_meas.x()), t_est[1] - T(t_meas.y()), t_est[2] - T(t_meas.z())};
    T dt_m[3];
    ceres::UnitQuaternionRotatePoint(qm, dt, dt_m);  // in the measurement's `from` frame
    for (int k = 0; k < 3; ++k) r[k] *= T(w_r), r[3 + k] = T(w_t) * dt_m[k];
    return true;
  }
  Vec3 t_meas;
  double q_meas_inv[4];
  double w_r, w_t;
};

struct Block {
  double q[4];  // w x y z
  double t[3];
};

double chi2_of(const BaObservation& o, const SE3& T_c_w, const Vec3& p_w, const PinholeCamera& cam,
               bool& in_front) {
  const Vec3 p = T_c_w * p_w;
  in_front = p.z() > 1e-3;
  if (!in_front) return 1e30;
  const double u = cam.fx * p.x() / p.z() + cam.cx, v = cam.fy * p.y() / p.z() + cam.cy;
  double e2 = (u - o.uv.x()) * (u - o.uv.x()) + (v - o.uv.y()) * (v - o.uv.y());
  double chi2 = e2 * o.inv_sigma2;
  if (const DepthRow depth(o); depth.present()) chi2 += depth.chi2(u, p.z(), cam.bf);
  return chi2;
}

bool solve(BaProblem& P, const PinholeCamera& cam, const BaConfig& cfg, const std::vector<char>& skip,
           int iterations) {
  std::vector<Block> blocks(P.T_c_w.size());
  for (std::size_t f = 0; f < blocks.size(); ++f) {
    const Quat q(P.T_c_w[f].linear());
    blocks[f] = {{q.w(), q.x(), q.y(), q.z()},
                 {P.T_c_w[f].translation().x(), P.T_c_w[f].translation().y(), P.T_c_w[f].translation().z()}};
  }
  ceres::Problem::Options popt;
  popt.loss_function_ownership = ceres::DO_NOT_TAKE_OWNERSHIP;
  popt.manifold_ownership = ceres::DO_NOT_TAKE_OWNERSHIP;
  ceres::Problem problem(popt);
  ceres::HuberLoss huber_mono(std::sqrt(cfg.chi2_mono)), huber_stereo(std::sqrt(cfg.chi2_stereo));
  ceres::QuaternionManifold quat_manifold;
  std::set<int> used_frames;
  for (std::size_t k = 0; k < P.obs.size(); ++k) {
    if (skip[k]) continue;
    const auto& o = P.obs[k];
    Block& b = blocks[o.frame];
    double* p = P.p_w[o.point].data();
    if (features::has_right(o.u_right))
      problem.AddResidualBlock(
          new ceres::AutoDiffCostFunction<ReprojectionCost<3>, 3, 4, 3, 3>(new ReprojectionCost<3>(o, cam)),
          &huber_stereo, b.q, b.t, p);
    else
      problem.AddResidualBlock(
          new ceres::AutoDiffCostFunction<ReprojectionCost<2>, 2, 4, 3, 3>(new ReprojectionCost<2>(o, cam)),
          &huber_mono, b.q, b.t, p);
    used_frames.insert(o.frame);
  }
  for (const BaPoseLink& l : P.links) {
    problem.AddResidualBlock(
        new ceres::AutoDiffCostFunction<PoseLinkCost, 6, 4, 3, 4, 3>(new PoseLinkCost(l)), nullptr,
        blocks[l.from].q, blocks[l.from].t, blocks[l.to].q, blocks[l.to].t);
    used_frames.insert(l.from), used_frames.insert(l.to);
  }
  if (used_frames.empty()) return false;
  for (int f : used_frames) {
    problem.SetManifold(blocks[f].q, &quat_manifold);
    if (P.fixed[f]) {
      problem.SetParameterBlockConstant(blocks[f].q);
      problem.SetParameterBlockConstant(blocks[f].t);
    }
  }
  ceres::Solver::Options opt;
  opt.linear_solver_type = ceres::SPARSE_SCHUR;
  opt.max_num_iterations = iterations;
  opt.num_threads = 1;
  opt.minimizer_progress_to_stdout = false;
  opt.logging_type = ceres::SILENT;
  ceres::Solver::Summary summary;
  ceres::Solve(opt, &problem, &summary);
  for (int f : used_frames)
    if (!P.fixed[f])
      P.T_c_w[f] = make_se3(Vec3(blocks[f].t[0], blocks[f].t[1], blocks[f].t[2]),
                            Quat(blocks[f].q[0], blocks[f].q[1], blocks[f].q[2], blocks[f].q[3]));
  return summary.IsSolutionUsable();
}

}  // namespace

BaObservation keypoint_ba_observation(const features::FrameFeatures& f, int idx, int frame, int point) {
  BaObservation o;
  o.frame = frame;
  o.point = point;
  set_keypoint_measurement(f, idx, o);
  return o;
}

void BaConfig::validate() const {
  require(first_iterations >= 1 && second_iterations >= 0, "ba: iterations must be >= 1 / >= 0");
  require(chi2_mono > 0 && chi2_stereo > 0, "ba: chi2 thresholds must be > 0");
  require(max_local_keyframes >= 1, "ba.max_local_keyframes must be >= 1");
  require(global_iterations >= 1, "ba.global_iterations must be >= 1");
  require(max_keyframe_step_deg > 0 && max_keyframe_step_m > 0,
          "ba: max_keyframe_step_deg and _m must be > 0");
}

int hold_keyframes_moved_too_far(const BaProblem& before, BaProblem& after, const BaConfig& config) {
  std::vector<char> linked(after.T_c_w.size(), 0);
  for (const BaPoseLink& l : before.links) linked[std::size_t(l.from)] = linked[std::size_t(l.to)] = 1;
  int n = 0;
  for (std::size_t f = 0; f < after.T_c_w.size(); ++f) {
    if (!before.fixed[f] && !linked[f] &&
        !poses_agree(after.T_c_w[f], before.T_c_w[f], config.max_keyframe_step_deg,
                     config.max_keyframe_step_m))
      after.fixed[f] = 1, ++n;
  }
  return n;
}

BaResult bundle_adjust(BaProblem& P, const PinholeCamera& cam, const BaConfig& cfg) {
  require(P.fixed.size() == P.T_c_w.size(), "bundle_adjust: one fixed flag per frame");
  for (const BaPoseLink& l : P.links)
    require(l.from >= 0 && l.to >= 0 && std::size_t(std::max(l.from, l.to)) < P.T_c_w.size() &&
                l.from != l.to && l.sigma_rad > 0 && l.sigma_m > 0,
            "bundle_adjust: a pose link needs two different frames of the problem and sigmas > 0");
  BaResult res;
  res.outlier.assign(P.obs.size(), 0);
  // 1. Robust solve, 2. drop the observations beyond the chi2 thresholds, 3. solve again.
  res.converged = solve(P, cam, cfg, res.outlier, cfg.first_iterations);
  auto classify = [&] {
    res.n_outliers = 0;
    for (std::size_t k = 0; k < P.obs.size(); ++k) {
      const auto& o = P.obs[k];
      bool in_front = true;
      const double chi2 = chi2_of(o, P.T_c_w[o.frame], P.p_w[o.point], cam, in_front);
      res.outlier[k] = !in_front || chi2 > (features::has_right(o.u_right) ? cfg.chi2_stereo : cfg.chi2_mono);
      res.n_outliers += res.outlier[k];
    }
  };
  classify();
  if (cfg.second_iterations > 0) {
    res.converged = solve(P, cam, cfg, res.outlier, cfg.second_iterations) && res.converged;
    classify();
  }
  return res;
}

}  // namespace s3m::slam
