#include "s3m/slam/loop/loop_geometry.hpp"

#include <Eigen/Geometry>
#include <random>

#include "s3m/core/error.hpp"

namespace s3m::slam {

void Se3RansacConfig::validate() const {
  require(max_iterations >= 1, "Se3RansacConfig.max_iterations must be >= 1");
  require(threshold_m > 0.0 && depth_ratio >= 0.0, "Se3RansacConfig: thresholds must be positive");
  require(min_inliers >= 3, "Se3RansacConfig.min_inliers must be >= 3");
}

SE3 fit_se3(const std::vector<Vec3>& p_a, const std::vector<Vec3>& p_b, const std::vector<int>& indices) {
  Eigen::Matrix3Xd src(3, indices.size()), dst(3, indices.size());
  for (size_t k = 0; k < indices.size(); ++k) {
    src.col(Eigen::Index(k)) = p_b[size_t(indices[k])];
    dst.col(Eigen::Index(k)) = p_a[size_t(indices[k])];
  }
  SE3 T = SE3::Identity();
  T.matrix() = Eigen::umeyama(src, dst, false);
  return T;
}

namespace {

std::vector<int> inliers_of(const SE3& T_a_b, const std::vector<Vec3>& p_a, const std::vector<Vec3>& p_b,
                            const Se3RansacConfig& c) {
  std::vector<int> in;
  for (size_t i = 0; i < p_a.size(); ++i) {
    const double tol = c.threshold_m + c.depth_ratio * std::abs(p_b[i].z());
    if ((p_a[i] - T_a_b * p_b[i]).squaredNorm() < tol * tol) in.push_back(int(i));
  }
  return in;
}

// Three points this close together or collinear give an ill-conditioned rotation.
bool well_spread(const Vec3& a, const Vec3& b, const Vec3& c) {
  return (b - a).cross(c - a).norm() > 1e-4 && (b - a).norm() > 0.01 && (c - a).norm() > 0.01;
}

}  // namespace

Se3RansacResult estimate_se3_ransac(const std::vector<Vec3>& p_a, const std::vector<Vec3>& p_b,
                                    const Se3RansacConfig& config) {
  config.validate();
  require(p_a.size() == p_b.size(), "estimate_se3_ransac: point lists differ in length");
  Se3RansacResult result;
  const int n = int(p_a.size());
  if (n < std::max(3, config.min_inliers)) return result;

  // 1. Hypotheses from random minimal samples; keep the one with most inliers.
  std::mt19937_64 rng(config.seed);
  std::uniform_int_distribution<int> pick(0, n - 1);
  std::vector<int> best;
  for (int it = 0; it < config.max_iterations; ++it) {
    const int i = pick(rng), j = pick(rng), k = pick(rng);
    if (i == j || j == k || i == k || !well_spread(p_b[size_t(i)], p_b[size_t(j)], p_b[size_t(k)])) continue;
    auto in = inliers_of(fit_se3(p_a, p_b, {i, j, k}), p_a, p_b, config);
    if (in.size() > best.size()) best = std::move(in);
    if (int(best.size()) > 0.8 * n) break;  // already overwhelming support
  }
  if (int(best.size()) < config.min_inliers) return result;

  // 2. Refine: least squares on the inliers, re-select, until the inlier set stops changing.
  SE3 T = fit_se3(p_a, p_b, best);
  for (int round = 0; round < 5; ++round) {
    auto in = inliers_of(T, p_a, p_b, config);
    if (int(in.size()) < config.min_inliers) break;
    const bool same = in == best;
    best = std::move(in);
    T = fit_se3(p_a, p_b, best);
    if (same) break;
  }
  double sq = 0.0;
  for (int i : best) sq += (p_a[size_t(i)] - T * p_b[size_t(i)]).squaredNorm();
  result.success = int(best.size()) >= config.min_inliers;
  result.T_a_b = T;
  result.rmse_m = std::sqrt(sq / double(best.size()));
  result.inliers = std::move(best);
  return result;
}

}  // namespace s3m::slam
