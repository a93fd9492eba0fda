#include "s3m/core/se3.hpp"

#include "s3m/core/error.hpp"

#include <Eigen/SVD>
#include <algorithm>
#include <cmath>

namespace s3m {

SE3 make_se3(const Vec3& t_m, const Quat& q) {
  SE3 T = SE3::Identity();
  T.linear() = q.normalized().toRotationMatrix();
  T.translation() = t_m;
  return T;
}

SE3 make_se3(const Mat3& R, const Vec3& t_m) {
  SE3 T = SE3::Identity();
  T.linear() = R;
  T.translation() = t_m;
  return T;
}

Mat3 skew(const Vec3& v) {
  Mat3 S;
  S << 0, -v.z(), v.y(), v.z(), 0, -v.x(), -v.y(), v.x(), 0;
  return S;
}

Mat3 so3_exp(const Vec3& phi) {
  const double theta = phi.norm();
  if (theta < 1e-12) return Mat3::Identity() + skew(phi);
  return Eigen::AngleAxisd(theta, phi / theta).toRotationMatrix();
}

Vec3 so3_log(const Mat3& R) {
  const Eigen::AngleAxisd aa(R);
  return aa.angle() * aa.axis();
}

bool poses_agree(const SE3& a, const SE3& b, double max_deg, double max_m) {
  const SE3 d = a * b.inverse();
  return rotation_angle_rad(d.linear()) <= max_deg * M_PI / 180.0 && d.translation().norm() <= max_m;
}

double rotation_angle_rad(const Mat3& R) {
  // atan2 of (sin, cos) instead of acos(cos): acos loses precision near 0 (an exact identity could
  // read as ~1e-8 rad), which matters for error metrics such as RPE.
  const double c = (R.trace() - 1.0) * 0.5;
  const double s = 0.5 * Vec3(R(2, 1) - R(1, 2), R(0, 2) - R(2, 0), R(1, 0) - R(0, 1)).norm();
  return std::atan2(s, c);
}

namespace {
// Left Jacobian of SO(3) and its inverse, needed to map translations of the twist.
Mat3 left_jacobian(const Vec3& phi) {
  const double theta = phi.norm();
  const Mat3 K = skew(phi);
  if (theta < 1e-8) return Mat3::Identity() + 0.5 * K;
  const double t2 = theta * theta;
  return Mat3::Identity() + (1 - std::cos(theta)) / t2 * K + (theta - std::sin(theta)) / (t2 * theta) * K * K;
}
}  // namespace

SE3 se3_exp(const Vec6& xi) {
  const Vec3 rho = xi.head<3>();
  const Vec3 phi = xi.tail<3>();
  return make_se3(so3_exp(phi), left_jacobian(phi) * rho);
}

Vec6 se3_log(const SE3& T) {
  const Vec3 phi = so3_log(T.linear());
  Vec6 xi;
  xi.head<3>() = left_jacobian(phi).inverse() * T.translation();
  xi.tail<3>() = phi;
  return xi;
}

SE3 se3_power(const SE3& T, double x) { return x == 1.0 ? T : se3_exp(x * se3_log(T)); }

SE3 orthonormalized(const SE3& T) {
  Eigen::JacobiSVD<Mat3> svd(T.linear(), Eigen::ComputeFullU | Eigen::ComputeFullV);
  Mat3 R = svd.matrixU() * svd.matrixV().transpose();
  if (R.determinant() < 0) {
    Mat3 U = svd.matrixU();
    U.col(2) *= -1;
    R = U * svd.matrixV().transpose();
  }
  return make_se3(R, T.translation());
}

SE3 weighted_mean(const std::vector<std::pair<SE3, double>>& poses) {
  require(!poses.empty(), "weighted_mean: no poses");
  const Mat3 R0 = poses.front().first.linear();
  Vec3 t = Vec3::Zero(), phi = Vec3::Zero();
  double sum = 0;
  for (const auto& [T, w] : poses) {
    require(w > 0, "weighted_mean: weights must be > 0");
    t += w * T.translation();
    phi += w * so3_log(R0.transpose() * T.linear());
    sum += w;
  }
  return make_se3(R0 * so3_exp(phi / sum), t / sum);
}

SE3 interpolate(const SE3& T0, const SE3& T1, double s) {
  const Quat q0(T0.linear()), q1(T1.linear());
  const Vec3 t = (1 - s) * T0.translation() + s * T1.translation();
  return make_se3(t, q0.slerp(s, q1));
}

}  // namespace s3m
