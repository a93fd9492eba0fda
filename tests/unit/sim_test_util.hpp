#pragma once
// Shared helpers for the simulator tests: small images keep the suite fast.
#include "s3m/sim/furniture.hpp"
#include "s3m/sim/renderer.hpp"
#include "s3m/sim/sensor.hpp"

namespace s3m::sim::test {

// Kinect-like intrinsics scaled down to w x h.
inline SensorConfig small_sensor(int w = 160, int h = 120, bool noise = false) {
  SensorConfig s;
  s.camera = sensor_camera("kinect", w, h);
  s.noise = noise;
  return s;
}

// An empty room [0,5] x [0,4] x [0,2.5] (shell only): every depth is known in closed form.
inline Scene empty_room() {
  Scene s;
  s.name = "empty";
  Rng rng(1);
  SceneBuilder b(s, rng);
  b.room({5.0, 4.0, 2.5}, mat(Pattern::kPaint, {0.8f, 0.8f, 0.8f}, {0.6f, 0.6f, 0.6f}, 0.3f),
         mat(Pattern::kTiles, {0.7f, 0.7f, 0.7f}, {0.3f, 0.3f, 0.3f}, 0.4f),
         mat(Pattern::kTiles, {0.9f, 0.9f, 0.9f}, {0.6f, 0.6f, 0.6f}, 0.6f));
  s.lights = {{Eigen::Vector3d(2.5, 2.0, 2.4), 1.0f}};
  s.flight_zone = {Eigen::Vector3d(1, 1, 0.5), Eigen::Vector3d(4, 3, 2)};
  return s;
}

// Camera at p_w [m] looking along world +x (optical z = world x, optical y = world -z).
inline SE3 looking_along_x(const Eigen::Vector3d& p_w) {
  SE3 T = SE3::Identity();
  T.linear() << 0, 0, 1, -1, 0, 0, 0, -1, 0;
  T.translation() = p_w;
  return T;
}

}  // namespace s3m::sim::test
