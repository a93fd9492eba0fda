#pragma once
// People walking through a simulated scene: each walks back and forth on a straight floor path at
// a steady pace, a capsule body with a head, labelled `person`. Everything is a pure function of
// the seed and the time, so frames can be rendered in any order and on any thread.
#include <cstdint>
#include <vector>

#include <Eigen/Core>

#include "s3m/sim/scene.hpp"
#include "s3m/sim/trajectory.hpp"

namespace s3m::config {
class FieldVisitor;
}

namespace s3m::sim {

struct PeopleConfig {
  int count = 0;              // people walking during the flight (0: a static scene, as before)
  double speed_mps = 1.1;     // mean walking speed; each person varies it by +-20 % [m/s]
  double min_path_m = 2.0;    // shortest walking path [m]
  double camera_gap_m = 0.8;  // people keep this horizontal distance from the camera at all times [m]
  void validate() const;
};
// Its YAML keys with the members they fill (core/config_table.hpp).
void fields(config::FieldVisitor& v, PeopleConfig& c);

struct Walker {
  Eigen::Vector2d a{0, 0}, b{0, 0};  // ends of the floor path [m]
  double speed_mps = 1.0;
  double phase_m = 0;      // distance along the back-and-forth walk at t = 0 [m]
  double height_m = 1.75;  // top of the head above the floor [m]
  double radius_m = 0.2;   // body capsule radius [m]
  Material clothes, skin;
  // Floor position and heading [rad] at time t_s.
  Eigen::Vector2d position(double t_s) const;
  double heading_rad(double t_s) const;
};

// Paths chosen per seed: inside the room, clear of furniture, never closer than
// camera_gap_m to the camera of `trajectory` while the camera flies below head height.
// When no path of a person keeps every rule, the one that keeps the camera farthest is taken.
std::vector<Walker> plan_walkers(const Scene& scene, const Trajectory& trajectory, const PeopleConfig& cfg,
                                 std::uint64_t seed);

// The primitives of walker `index` at time t_s, labelled person (object_id -1: not a scene object).
std::vector<Primitive> walker_primitives(const Walker& walker, double t_s);

}  // namespace s3m::sim
