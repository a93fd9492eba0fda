#pragma once
// Trajectory shapes: position and heading as smooth functions of normalised time s in [0, 1].
// Internal to the simulator (trajectory.cpp turns them into robot and camera poses).
#include <cstdint>
#include <functional>
#include <string>

#include <Eigen/Core>

#include "s3m/sim/scene.hpp"

namespace s3m::sim::detail {

struct Kinematic {
  Eigen::Vector3d p_w{0, 0, 0};  // robot position [m]
  double yaw_rad = 0;            // heading about world z
  double pitch_rad = 0;          // extra attitude (handheld shake); UAV tilt is derived from acceleration
  double roll_rad = 0;
};

struct ShapeParams {
  Aabb zone;            // flight zone of the scene
  double duration_s;    // total duration
  double extent = 1.0;  // lateral scale in (0, 1]; reduced by the caller to respect the speed limit
  std::uint64_t seed = 0;
};

using PathFn = std::function<Kinematic(double s)>;

// Returns the shape for a trajectory type, or an empty function for an unknown type.
PathFn make_shape(const std::string& type, const ShapeParams& params);
// True for types flown by a UAV (attitude tilts with acceleration); false for handheld.
bool is_uav(const std::string& type);
// Shortest duration [s] at which a type keeps realistic speeds and turn rates; shorter sequences
// show the beginning of the nominal flight rather than a sped-up version of all of it.
double nominal_duration_s(const std::string& type);

}  // namespace s3m::sim::detail
