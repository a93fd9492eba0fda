#pragma once
// Rigid transforms. Naming: T_a_b maps points expressed in frame b into frame a,
// so p_a = T_a_b * p_b and T_a_c = T_a_b * T_b_c. Translations in metres, angles in radians.
#include <Eigen/Core>
#include <Eigen/Geometry>
#include <utility>
#include <vector>

namespace s3m {

using SE3 = Eigen::Isometry3d;
using Vec3 = Eigen::Vector3d;
using Vec6 = Eigen::Matrix<double, 6, 1>;  // twist [rho (m); phi (rad)]
using Mat3 = Eigen::Matrix3d;
using Quat = Eigen::Quaterniond;

// Builds T from a translation [m] and a (not necessarily normalised) quaternion.
SE3 make_se3(const Vec3& t_m, const Quat& q);
SE3 make_se3(const Mat3& R, const Vec3& t_m);

// Rotation / twist exponential and logarithm maps (SO(3), SE(3)).
Mat3 so3_exp(const Vec3& phi_rad);
Vec3 so3_log(const Mat3& R);
SE3 se3_exp(const Vec6& xi);
Vec6 se3_log(const SE3& T);
// T^x: the constant-velocity motion T applied x times (x = 1: T itself, bit for bit; x may be
// fractional or negative).
SE3 se3_power(const SE3& T, double x);

// Rotation angle of R in radians, in [0, pi].
double rotation_angle_rad(const Mat3& R);

// Whether two estimates of one transform agree: a * b^-1 turns by at most max_deg [deg] and moves by
// at most max_m [m]. E.g. two frame-to-frame motions T_cur_prev, two poses T_c_w of one frame, or a
// keyframe pose before and after an optimisation.
bool poses_agree(const SE3& a, const SE3& b, double max_deg, double max_m);

// Re-orthonormalises the rotation part (SVD) so accumulated products stay in SO(3).
SE3 orthonormalized(const SE3& T);

// Geodesic interpolation between T0 (s=0) and T1 (s=1).
SE3 interpolate(const SE3& T0, const SE3& T1, double s);

// Weighted mean of nearby poses (weights > 0, at least one pose): translations averaged, rotations
// by the weighted mean of their so3_log about the first pose's rotation. Exact for rotations about
// one axis within pi of the first; meant for estimates of one pose that differ by a few degrees.
SE3 weighted_mean(const std::vector<std::pair<SE3, double>>& poses);

// Skew-symmetric matrix [v]x.
Mat3 skew(const Vec3& v);

// One entry of a trajectory: a pose and its time stamp.
struct StampedPose {
  double t_s = 0.0;             // [s]
  SE3 T_w_x = SE3::Identity();  // x = camera, robot or keyframe frame, w = the trajectory's world frame [m]
};

// The paper's calibration equation, the one place the robot pose is composed: robot-to-world
// T_w_r from camera-to-world T_w_c and the robot-to-camera calibration T_c_r (maps robot-frame
// points into the camera frame; `slam.T_c_r` in a preset). Any world works: T_map_r from T_map_c.
inline SE3 robot_pose(const SE3& T_w_c, const SE3& T_c_r) { return T_w_c * T_c_r; }

}  // namespace s3m
