// DepthOdometry::align_observable(): point-to-plane ICP that updates only the directions the view
// constrains (depth_odometry.hpp).
#include <algorithm>
#include <cmath>
#include <limits>
#include <vector>

#include <Eigen/Eigenvalues>
#include <opencv2/core.hpp>

#include "s3m/slam/odometry/depth_odometry.hpp"

namespace s3m::slam {
namespace {

using Mat6 = Eigen::Matrix<double, 6, 6>;

struct Intrinsics {
  double fx, fy, cx, cy;
};

// Vertex map (camera frame, NaN = no depth) of a depth image in metres.
cv::Mat_<cv::Vec3f> vertices(const cv::Mat& depth, const Intrinsics& k) {
  const float nan = std::numeric_limits<float>::quiet_NaN();
  cv::Mat_<cv::Vec3f> v(depth.size(), cv::Vec3f(nan, nan, nan));
  for (int r = 0; r < depth.rows; ++r)
    for (int c = 0; c < depth.cols; ++c) {
      const float z = depth.at<float>(r, c);
      if (std::isfinite(z))
        v(r, c) = cv::Vec3f(float((c - k.cx) / k.fx * z), float((r - k.cy) / k.fy * z), z);
    }
  return v;
}

// Normals from central differences, facing the camera; none across a depth step of more than
// max_diff (the two sides are different surfaces).
cv::Mat_<cv::Vec3f> normals(const cv::Mat_<cv::Vec3f>& v, double max_diff) {
  const float nan = std::numeric_limits<float>::quiet_NaN();
  cv::Mat_<cv::Vec3f> n(v.size(), cv::Vec3f(nan, nan, nan));
  for (int r = 1; r + 1 < v.rows; ++r)
    for (int c = 1; c + 1 < v.cols; ++c) {
      const cv::Vec3f &p = v(r, c), &l = v(r, c - 1), &rt = v(r, c + 1), &u = v(r - 1, c), &d = v(r + 1, c);
      bool ok = std::isfinite(p[2]);
      for (const cv::Vec3f* q : {&l, &rt, &u, &d})
        ok = ok && std::isfinite((*q)[2]) && std::abs((*q)[2] - p[2]) < max_diff;
      if (!ok) continue;
      cv::Vec3f m = (rt - l).cross(d - u);
      const float len = float(cv::norm(m));
      if (len <= 0) continue;
      m /= len;
      n(r, c) = m.dot(p) > 0 ? -m : m;
    }
  return n;
}

// The normal equations of the point-to-plane residuals r = n . (T q - v) over projective
// correspondences, for the update T <- [exp(omega) | t] T: dr/domega = (p x n) / d (rotations
// scaled by the depth d), dr/dt = n. Huber-weighted.
struct Normal {
  Mat6 H = Mat6::Zero();
  Vec6 b = Vec6::Zero();
  int n = 0;
  double sse = 0;
};

struct Target {
  cv::Mat_<cv::Vec3f> v, n;  // the previous frame's vertices and normals
  Intrinsics k;
  double max_diff, huber, d;
};

Normal normal_equations(const std::vector<Vec3>& source, const Target& t, const SE3& T_prev_cur) {
  Normal eq;
  for (const Vec3& q : source) {
    const Vec3 p = T_prev_cur * q;
    if (p.z() <= 0) continue;
    const int u = int(std::lround(t.k.fx * p.x() / p.z() + t.k.cx)),
              v = int(std::lround(t.k.fy * p.y() / p.z() + t.k.cy));
    if (u < 0 || v < 0 || u >= t.v.cols || v >= t.v.rows) continue;
    const cv::Vec3f tv = t.v(v, u), tn = t.n(v, u);
    if (!std::isfinite(tn[2])) continue;
    const Vec3 vt(tv[0], tv[1], tv[2]), nt(tn[0], tn[1], tn[2]);
    if ((p - vt).norm() > t.max_diff) continue;
    const double r = nt.dot(p - vt);
    Vec6 J;
    J << p.cross(nt) / t.d, nt;
    const double w = std::abs(r) <= t.huber ? 1.0 : t.huber / std::abs(r);
    eq.H += w * J * J.transpose();
    eq.b += w * J * r;
    eq.sse += r * r;
    ++eq.n;
  }
  return eq;
}

// The Gauss-Newton step restricted to the eigenvectors with at least min_information: the
// solution remapping (Zhang et al. 2016); along the others the estimate stays where it started.
Vec6 observable_step(const Normal& eq, double min_information, int& observed) {
  const Eigen::SelfAdjointEigenSolver<Mat6> es(eq.H);
  Vec6 step = Vec6::Zero();
  observed = 0;
  for (int i = 0; i < 6; ++i) {
    if (es.eigenvalues()(i) < min_information) continue;
    ++observed;
    step -= es.eigenvectors().col(i) * (es.eigenvectors().col(i).dot(eq.b) / es.eigenvalues()(i));
  }
  return step;
}

double median_depth(const std::vector<Vec3>& points) {
  std::vector<double> z(points.size());
  std::transform(points.begin(), points.end(), z.begin(), [](const Vec3& q) { return q.z(); });
  std::nth_element(z.begin(), z.begin() + z.size() / 2, z.end());
  return z[z.size() / 2];
}

}  // namespace

std::optional<ObservableMotion> DepthOdometry::align_observable(const RgbdFrame& prev, const RgbdFrame& cur,
                                                                const SE3& T_cur_prev_guess) const {
  constexpr int kMinPoints = 100, kIterations = 20;
  const cv::Mat depth0 = prepare_depth(prev), depth1 = prepare_depth(cur);  // depth only: no colour term
  const Intrinsics k{K_.at<float>(0, 0), K_.at<float>(1, 1), K_.at<float>(0, 2), K_.at<float>(1, 2)};
  // 1. Target: the previous frame's vertices and normals; source: the current frame's vertices.
  Target target{vertices(depth0, k), {}, k, config_.max_depth_diff_m, config_.max_depth_diff_m / 4, 1.0};
  target.n = normals(target.v, config_.max_depth_diff_m);
  std::vector<Vec3> source;
  for (const cv::Vec3f& q : vertices(depth1, k))
    if (std::isfinite(q[2])) source.emplace_back(q[0], q[1], q[2]);
  if (int(source.size()) < kMinPoints) return std::nullopt;
  target.d = median_depth(source);  // rotations scaled by it: all six directions in metres at the scene
  // 2. Gauss-Newton from the guess, each step only along the directions the points constrain.
  SE3 T_prev_cur = T_cur_prev_guess.inverse();
  ObservableMotion out;
  for (int it = 0; it < kIterations; ++it) {
    const Normal eq = normal_equations(source, target, T_prev_cur);
    if (eq.n < kMinPoints) return std::nullopt;
    const Vec6 step = observable_step(eq, config_.min_observed_ratio * eq.n, out.observed_directions);
    const Vec3 omega = step.head<3>() / target.d, t = step.tail<3>();
    T_prev_cur = orthonormalized(make_se3(so3_exp(omega), t) * T_prev_cur);
    out.n_points = eq.n;
    out.inlier_fraction = double(eq.n) / double(source.size());
    out.rms_m = std::sqrt(eq.sse / eq.n);
    if (omega.norm() < 1e-7 && t.norm() < 1e-7) break;
  }
  out.T_cur_prev = T_prev_cur.inverse();
  return out;
}

}  // namespace s3m::slam
