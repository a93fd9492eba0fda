#pragma once
// Smooth robot trajectories through a scene's flight zone, and the camera poses derived from
// them with the camera-to-robot calibration: T_w_c = T_w_r * T_r_c, T_r_c = T_c_r^-1.
// Robot body frame: x forward, y left, z up (ROS REP 103). Camera frame: x right, y down, z forward.
#include <cstdint>
#include <functional>
#include <string>
#include <vector>

#include <yaml-cpp/yaml.h>

#include "s3m/core/se3.hpp"
#include "s3m/sim/scene.hpp"

namespace s3m::config {
class FieldVisitor;
}

namespace s3m::sim {

// Camera mounting on the robot: position [m] in the robot frame and a downward pitch [deg]
// (plus optional yaw/roll [deg]); converted to T_c_r by camera_to_robot().
struct CameraMount {
  Eigen::Vector3d position_r_m{0.10, 0.0, -0.03};
  double pitch_down_deg = 12.0;
  double yaw_deg = 0.0;  // positive: camera turned to the left
  double roll_deg = 0.0;
};
SE3 camera_to_robot(const CameraMount& mount);  // returns T_c_r

struct TrajectoryConfig {
  // uav_sweep: take-off, hover, a full yaw sweep, forward flight out and back;
  // figure8: lemniscate at constant height, heading along the path, ends where it started;
  // lawnmower: back-and-forth rows across the zone; loop: a circuit looking outwards that
  // passes the start again (loop closure); handheld: walking with head bob and hand shake;
  // handheld_pan: the same walk while panning +-60 deg every 4 s (~65 deg/s median turn rate);
  // hover: near-static hovering with slow drift; forward: straight flight along the long axis and back.
  std::string type = "uav_sweep";
  int frames = 300;
  double fps = 30.0;
  double start_time_s = 1.0;  // timestamp of frame 0 (TUM files key on time; keep it > 0)
  CameraMount mount;
  void validate() const;
};
std::vector<std::string> trajectory_types();
void load_trajectory_config(const YAML::Node& node, TrajectoryConfig& cfg, const std::string& ctx);
// Its YAML keys with the members they fill (core/config_table.hpp).
void fields(config::FieldVisitor& v, TrajectoryConfig& c);

struct TrajectorySample {
  double t_s = 0;
  SE3 T_w_r = SE3::Identity();  // robot body in world
  SE3 T_w_c = SE3::Identity();  // camera in world
};

struct Trajectory {
  std::string type;
  SE3 T_c_r = SE3::Identity();
  std::vector<TrajectorySample> samples;
  // The robot pose T_w_r at any time t_s [s], also between and beyond the samples: the flight's own
  // smooth path, which sensor timing effects need. Empty for hand-made trajectories.
  std::function<SE3(double t_s)> robot_path;
  // Robot / camera pose at t_s: robot_path, or without it geodesic interpolation between the
  // samples (held constant outside them).
  SE3 T_w_r_at(double t_s) const;
  SE3 T_w_c_at(double t_s) const;
  double max_speed_mps() const;
  double length_m() const;
};

// Samples cfg.frames poses at cfg.fps. Each type has a nominal duration (hover 4 s, handheld 12 s,
// forward 14 s, lawnmower 16 s, others 10 s); longer sequences stretch the shape (slower), shorter ones
// show its beginning, so speeds (<= 1.5 m/s) and turn rates stay realistic either way.
// The seed varies start heading and handheld shake.
// Throws s3m::Error for an unknown type or if a pose would leave the room or come within
// 0.2 m of furniture (the presets' flight zones are designed so this does not happen).
Trajectory make_trajectory(const Scene& scene, const TrajectoryConfig& cfg, std::uint64_t seed);

}  // namespace s3m::sim
