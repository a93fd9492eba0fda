#include "s3m/sim/trajectory.hpp"

#include <algorithm>
#include <cmath>

#include "s3m/core/config_table.hpp"
#include "s3m/core/error.hpp"
#include "s3m/core/yaml_util.hpp"
#include "s3m/sim/trajectory_shapes.hpp"

namespace s3m::sim {
namespace {

constexpr double kGravity = 9.81;      // [m/s^2]
constexpr double kMaxSpeed = 1.5;      // [m/s] shapes shrink until they respect it
constexpr double kMinClearance = 0.2;  // [m] robot centre to furniture
constexpr double kDeg = M_PI / 180.0;

Mat3 rot(const Vec3& axis, double angle_rad) { return Eigen::AngleAxisd(angle_rad, axis).toRotationMatrix(); }

// Quadrotor attitude: body z along thrust (acceleration + gravity), body x as close to the
// heading as that allows (differential flatness, Mellinger & Kumar 2011).
Mat3 uav_attitude(const Vec3& acc_w, double yaw_rad) {
  const Vec3 z_b = (acc_w + Vec3(0, 0, kGravity)).normalized();
  const Vec3 x_c(std::cos(yaw_rad), std::sin(yaw_rad), 0);
  const Vec3 y_b = z_b.cross(x_c).normalized();
  Mat3 R;
  R << y_b.cross(z_b), y_b, z_b;
  return R;
}

SE3 robot_pose_on_path(const detail::PathFn& path, double s, double duration_s, bool uav) {
  const detail::Kinematic k = path(s);
  SE3 T = SE3::Identity();
  T.translation() = k.p_w;
  if (uav) {
    // 10 ms central difference; shapes extend smoothly beyond [0, 1] (they start and end at rest).
    const double ds = 0.01 / duration_s;
    const Vec3 acc = (path(s + ds).p_w - 2.0 * k.p_w + path(s - ds).p_w) / (0.01 * 0.01);
    T.linear() = uav_attitude(acc, k.yaw_rad);
  } else {
    T.linear() =
        rot(Vec3::UnitZ(), k.yaw_rad) * rot(Vec3::UnitY(), k.pitch_rad) * rot(Vec3::UnitX(), k.roll_rad);
  }
  return T;
}

double max_speed(const detail::PathFn& path, double duration_s, int n) {
  double v = 0;
  for (int i = 0; i < n; ++i) {
    const double s0 = static_cast<double>(i) / n, s1 = static_cast<double>(i + 1) / n;
    v = std::max(v, (path(s1).p_w - path(s0).p_w).norm() / (duration_s / n));
  }
  return v;
}

}  // namespace

SE3 camera_to_robot(const CameraMount& m) {
  // Optical axes in the robot frame before tilting: z_c = x_r (forward), x_c = -y_r, y_c = -z_r.
  Mat3 R_r_c0;
  R_r_c0 << 0, 0, 1, -1, 0, 0, 0, -1, 0;
  SE3 T_r_c = SE3::Identity();
  // Positive pitch about the robot's y axis tips the optical axis downwards.
  T_r_c.linear() = rot(Vec3::UnitZ(), m.yaw_deg * kDeg) * rot(Vec3::UnitY(), m.pitch_down_deg * kDeg) *
                   rot(Vec3::UnitX(), m.roll_deg * kDeg) * R_r_c0;
  T_r_c.translation() = m.position_r_m;
  return T_r_c.inverse();
}

void TrajectoryConfig::validate() const {
  require(frames >= 1, "trajectory: frames must be >= 1");
  require(fps > 0, "trajectory: fps must be > 0");
  require(start_time_s >= 0, "trajectory: start_time_s must be >= 0");
  require(std::abs(mount.pitch_down_deg) <= 90, "trajectory: camera pitch_down_deg must be within [-90, 90]");
  const auto types = trajectory_types();
  if (std::find(types.begin(), types.end(), type) == types.end()) {
    std::string list;
    for (const auto& t : types) list += (list.empty() ? "" : ", ") + t;
    throw Error("unknown trajectory type '" + type + "' (expected one of: " + list + ")");
  }
}

std::vector<std::string> trajectory_types() {
  return {"uav_sweep", "figure8", "loop", "lawnmower", "handheld", "handheld_pan", "hover", "forward"};
}

void fields(config::FieldVisitor& v, TrajectoryConfig& c) {
  v("type", c.type);
  v("frames", c.frames);
  v("fps", c.fps);
  v("start_time_s", c.start_time_s);
  // The camera mount's keys sit flat in `trajectory:` (camera_*).
  Vec3& pos = c.mount.position_r_m;
  v("camera_position_r_m",
    config::Custom{[&pos](const YAML::Node& n, const std::string& key, const std::string& ctx) {
                     const auto xyz = yaml_as<std::vector<double>>(n, key, ctx);
                     if (xyz.size() != 3) throw ParseError(ctx, n.Mark().line + 1, "bad " + key, "[x, y, z]");
                     pos = Vec3(xyz[0], xyz[1], xyz[2]);
                   },
                   [&pos] {
                     YAML::Node n(YAML::NodeType::Sequence);
                     for (int i = 0; i < 3; ++i) n.push_back(config::format_number(pos[i]));
                     n.SetStyle(YAML::EmitterStyle::Flow);
                     return n;
                   }});
  v("camera_pitch_down_deg", c.mount.pitch_down_deg);
  v("camera_yaw_deg", c.mount.yaw_deg);
  v("camera_roll_deg", c.mount.roll_deg);
}

void load_trajectory_config(const YAML::Node& n, TrajectoryConfig& c, const std::string& ctx) {
  config::read(n, config::table_of(c), ctx);
}

double Trajectory::max_speed_mps() const {
  double v = 0;
  for (std::size_t i = 1; i < samples.size(); ++i)
    v = std::max(v, (samples[i].T_w_r.translation() - samples[i - 1].T_w_r.translation()).norm() /
                        (samples[i].t_s - samples[i - 1].t_s));
  return v;
}

SE3 Trajectory::T_w_r_at(double t_s) const {
  if (robot_path) return robot_path(t_s);
  require(!samples.empty(), "Trajectory::T_w_r_at: no samples");
  const auto after = std::upper_bound(samples.begin(), samples.end(), t_s,
                                      [](double t, const TrajectorySample& s) { return t < s.t_s; });
  if (after == samples.begin()) return samples.front().T_w_r;
  if (after == samples.end()) return samples.back().T_w_r;
  const TrajectorySample& a = *(after - 1);
  return interpolate(a.T_w_r, after->T_w_r, (t_s - a.t_s) / (after->t_s - a.t_s));
}

SE3 Trajectory::T_w_c_at(double t_s) const { return T_w_r_at(t_s) * T_c_r.inverse(); }

double Trajectory::length_m() const {
  double l = 0;
  for (std::size_t i = 1; i < samples.size(); ++i)
    l += (samples[i].T_w_r.translation() - samples[i - 1].T_w_r.translation()).norm();
  return l;
}

Trajectory make_trajectory(const Scene& scene, const TrajectoryConfig& cfg, std::uint64_t seed) {
  cfg.validate();
  const double seq_s = std::max(cfg.frames - 1, 1) / cfg.fps;
  const double duration_s = std::max(seq_s, detail::nominal_duration_s(cfg.type));
  // 1. Build the shape, shrinking it until its peak speed respects the UAV limit.
  detail::ShapeParams params{scene.flight_zone, duration_s, 1.0, seed};
  detail::PathFn path = detail::make_shape(cfg.type, params);
  for (int it = 0; it < 6; ++it) {
    const double v = max_speed(path, duration_s, 1000);
    if (v <= kMaxSpeed) break;
    params.extent *= 0.97 * kMaxSpeed / v;
    path = detail::make_shape(cfg.type, params);
  }
  // 2. Sample robot poses and derive camera poses.
  Trajectory traj;
  traj.type = cfg.type;
  traj.T_c_r = camera_to_robot(cfg.mount);
  const SE3 T_r_c = traj.T_c_r.inverse();
  const bool uav = detail::is_uav(cfg.type);
  traj.robot_path = [path, duration_s, uav, t0 = cfg.start_time_s](double t_s) {
    return robot_pose_on_path(path, (t_s - t0) / duration_s, duration_s, uav);
  };
  for (int i = 0; i < cfg.frames; ++i) {
    const double s = (i / cfg.fps) / duration_s;
    TrajectorySample smp;
    smp.t_s = cfg.start_time_s + i / cfg.fps;
    smp.T_w_r = robot_pose_on_path(path, s, duration_s, uav);
    smp.T_w_c = smp.T_w_r * T_r_c;
    // 3. Safety: the robot must stay in the room and clear of furniture.
    const Vec3 p = smp.T_w_r.translation();
    const double clearance = scene.clearance_m(p);
    if (clearance < kMinClearance)
      throw Error("trajectory '" + cfg.type + "' in scene '" + scene.name + "': frame " + std::to_string(i) +
                  " at (" + std::to_string(p.x()) + ", " + std::to_string(p.y()) + ", " +
                  std::to_string(p.z()) + ") is only " + std::to_string(clearance) +
                  " m from an obstacle (need " + std::to_string(kMinClearance) + " m)");
    traj.samples.push_back(smp);
  }
  return traj;
}

}  // namespace s3m::sim
