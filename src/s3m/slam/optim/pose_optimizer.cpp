#include "s3m/slam/optim/pose_optimizer.hpp"

#include <cmath>

#include <Eigen/Cholesky>

#include "s3m/core/error.hpp"

namespace s3m::slam {
namespace {

constexpr double kMinDepthM = 1e-3;

// Whitened residual e = (predicted - measured) / sigma (2 or 3 rows) and de/dxi for a left
// perturbation T_c_w <- exp(xi) * T_c_w, xi = [rho; phi]. The depth row is DepthRow's.
int residual_and_jacobian(const PoseObservation& o, const SE3& T_c_w, const PinholeCamera& cam,
                          Eigen::Vector3d& e, Eigen::Matrix<double, 3, 6>& J) {
  const Vec3 p = T_c_w * o.p_w;
  if (p.z() < kMinDepthM) return 0;
  const double iz = 1.0 / p.z(), iz2 = iz * iz;
  const double u = cam.fx * p.x() * iz + cam.cx, v = cam.fy * p.y() * iz + cam.cy;
  const double w = std::sqrt(o.inv_sigma2);
  Eigen::Matrix<double, 3, 3> Jp;               // d(u, v, depth row) / d p_c, whitened
  Jp << cam.fx * iz, 0, -cam.fx * p.x() * iz2,  //
      0, cam.fy * iz, -cam.fy * p.y() * iz2,    //
      0, 0, 0;
  e << u - o.uv.x(), v - o.uv.y(), 0;
  Jp *= w;
  e *= w;
  const DepthRow depth(o);
  e(2) = depth.residual(u, iz, cam.bf);
  Jp.row(2) = depth.jacobian(p, cam);
  Eigen::Matrix<double, 3, 6> Jx;  // d p_c / d xi = [I, -[p]x]
  Jx.leftCols<3>().setIdentity();
  Jx.rightCols<3>() = -skew(p);
  J = Jp * Jx;
  return features::has_right(o.u_right) ? 3 : 2;
}

}  // namespace

void PoseOptimizerConfig::validate() const {
  require(rounds >= 1 && iterations >= 1, "pose optimizer: rounds and iterations must be >= 1");
  require(chi2_mono > 0 && chi2_stereo > 0, "pose optimizer: chi2 thresholds must be > 0");
}

PoseObservation keypoint_observation(const features::FrameFeatures& f, int i, const Vec3& p_w) {
  PoseObservation o;
  o.p_w = p_w;
  set_keypoint_measurement(f, i, o);
  return o;
}

bool fits_pose(const PoseObservation& o, const SE3& T_c_w, const PinholeCamera& camera,
               const PoseOptimizerConfig& config) {
  double chi2 = 0;
  const bool in_front = reprojection_chi2(o, T_c_w, camera, chi2);
  return in_front && chi2 <= (features::has_right(o.u_right) ? config.chi2_stereo : config.chi2_mono);
}

bool reprojection_chi2(const PoseObservation& o, const SE3& T_c_w, const PinholeCamera& camera,
                       double& chi2) {
  Eigen::Vector3d e;
  Eigen::Matrix<double, 3, 6> J;
  const int rows = residual_and_jacobian(o, T_c_w, camera, e, J);
  if (rows == 0) return false;
  chi2 = e.head(rows).squaredNorm();
  return true;
}

PoseOptimizerResult optimize_pose(const std::vector<PoseObservation>& obs, const SE3& T_c_w_init,
                                  const PinholeCamera& camera, const PoseOptimizerConfig& config) {
  const int n = static_cast<int>(obs.size());
  PoseOptimizerResult res;
  res.T_c_w = T_c_w_init;
  res.inlier.assign(n, 1);
  Eigen::Vector3d e;
  Eigen::Matrix<double, 3, 6> J;
  for (int round = 0; round < config.rounds; ++round) {
    const bool robust = round + 1 < config.rounds;
    // 1. Robust Gauss-Newton on the current inliers.
    for (int it = 0; it < config.iterations; ++it) {
      Eigen::Matrix<double, 6, 6> H = Eigen::Matrix<double, 6, 6>::Zero();
      Eigen::Matrix<double, 6, 1> b = Eigen::Matrix<double, 6, 1>::Zero();
      int used = 0;
      for (int i = 0; i < n; ++i) {
        if (!res.inlier[i]) continue;
        const int rows = residual_and_jacobian(obs[i], res.T_c_w, camera, e, J);
        if (rows == 0) continue;
        const double chi2 = e.head(rows).squaredNorm();
        const double delta = std::sqrt(rows == 3 ? config.chi2_stereo : config.chi2_mono);
        const double r = std::sqrt(chi2);
        const double w = (robust && r > delta) ? delta / r : 1.0;
        H.noalias() += w * J.topRows(rows).transpose() * J.topRows(rows);
        b.noalias() += w * J.topRows(rows).transpose() * e.head(rows);
        ++used;
      }
      if (used < 3) break;
      H.diagonal().array() += 1e-9;
      const Eigen::Matrix<double, 6, 1> xi = -H.ldlt().solve(b);
      if (!xi.allFinite()) break;
      res.T_c_w = orthonormalized(se3_exp(xi) * res.T_c_w);
      if (xi.squaredNorm() < 1e-14) break;
    }
    // 2. Reclassify every observation (outliers may come back).
    for (int i = 0; i < n; ++i) res.inlier[i] = fits_pose(obs[i], res.T_c_w, camera, config);
  }
  res.n_inliers = 0;
  for (char c : res.inlier) res.n_inliers += c;
  return res;
}

}  // namespace s3m::slam
