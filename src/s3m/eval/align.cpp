#include "s3m/eval/align.hpp"

#include <Eigen/Geometry>

#include "s3m/core/error.hpp"

namespace s3m::eval {

AlignMode parse_align_mode(const std::string& name) {
  if (name == "none") return AlignMode::kNone;
  if (name == "se3") return AlignMode::kSe3;
  if (name == "sim3") return AlignMode::kSim3;
  throw Error("unknown alignment '" + name + "' (expected se3, sim3 or none)");
}

std::string to_string(AlignMode mode) {
  switch (mode) {
    case AlignMode::kNone: return "none";
    case AlignMode::kSe3: return "se3";
    case AlignMode::kSim3: return "sim3";
  }
  return "?";
}

SE3 Sim3::apply(const SE3& T_est_x) const {
  SE3 T = SE3::Identity();
  T.linear() = T_gt_est.linear() * T_est_x.linear();
  T.translation() = apply(Vec3(T_est_x.translation()));
  return T;
}

Sim3 align_positions(const std::vector<Vec3>& p_est, const std::vector<Vec3>& p_gt, AlignMode mode) {
  require(p_est.size() == p_gt.size(), "align_positions: estimate and ground truth differ in length");
  if (mode == AlignMode::kNone) return {};
  require(p_est.size() >= 3, "align_positions: need at least 3 matched poses to align (got " +
                                 std::to_string(p_est.size()) + ")");
  Eigen::Matrix3Xd src(3, p_est.size()), dst(3, p_gt.size());
  for (std::size_t i = 0; i < p_est.size(); ++i) {
    src.col(static_cast<Eigen::Index>(i)) = p_est[i];
    dst.col(static_cast<Eigen::Index>(i)) = p_gt[i];
  }
  // Eigen's umeyama returns [sR t; 0 1]; it handles the reflection case (det = -1) as Umeyama's paper.
  const Eigen::Matrix4d M = Eigen::umeyama(src, dst, mode == AlignMode::kSim3);
  Sim3 out;
  const Mat3 sR = M.topLeftCorner<3, 3>();
  out.scale = std::cbrt(sR.determinant());
  out.T_gt_est.linear() = sR / out.scale;
  out.T_gt_est.translation() = M.topRightCorner<3, 1>();
  return out;
}

}  // namespace s3m::eval
