#pragma once
// Least-squares alignment of an estimated trajectory to ground truth (Umeyama 1991, which equals
// Horn's closed form used by TUM's evaluate_ate.py when the scale is fixed to 1).
#include <string>
#include <vector>

#include "s3m/core/se3.hpp"

namespace s3m::eval {

enum class AlignMode { kNone, kSe3, kSim3 };
AlignMode parse_align_mode(const std::string& name);  // "none" | "se3" | "sim3"; s3m::Error otherwise
std::string to_string(AlignMode mode);

// p_gt ~= scale * T_gt_est.rotation() * p_est + T_gt_est.translation().
struct Sim3 {
  SE3 T_gt_est = SE3::Identity();
  double scale = 1.0;

  Vec3 apply(const Vec3& p_est) const { return scale * (T_gt_est.linear() * p_est) + T_gt_est.translation(); }
  // A whole pose: rotation rotated, position mapped as a point (so the camera stays on the aligned path).
  SE3 apply(const SE3& T_est_x) const;
};

// Minimises sum |p_gt_i - (s R p_est_i + t)|^2 (s = 1 unless kSim3; identity for kNone).
// Needs >= 3 pairs for kSe3/kSim3 (s3m::Error otherwise); the inputs must have equal length.
Sim3 align_positions(const std::vector<Vec3>& p_est, const std::vector<Vec3>& p_gt, AlignMode mode);

}  // namespace s3m::eval
