#pragma once
// Two flights through one simulated office (issue 23): the same building (--layout-seed 3), two
// different camera trajectories and noise seeds. Flight A is the simulator's figure-eight (office
// layout 3, seed 3, 300 frames, 30 Hz), the map-building session. Flight B flies the figure-eight
// again with the camera mounted 20 deg to the left and pitched 5 instead of 12 deg down (seed 5,
// 240 frames: the first 80 % of the shape), so every view of B differs from A's while staying in
// the area A mapped. Flight C (below) starts where A never looked. Rendered once and cached across
// test processes (cached_folder.hpp).
#include <filesystem>
#include <string>

#include "s3m/sim/simulate.hpp"

#include "cached_folder.hpp"

namespace s3m::it {

inline constexpr std::uint64_t kSessionLayout = 3;

inline sim::SimConfig flight_a_config() {
  sim::SimConfig c;
  c.scene = "office";
  c.layout_seed = kSessionLayout;
  c.seed = 3;
  c.trajectory.type = "figure8";
  c.trajectory.frames = 300;
  return c;
}

inline sim::SimConfig flight_b_config() {
  sim::SimConfig c = flight_a_config();
  c.seed = 5;
  c.trajectory.frames = 240;
  c.trajectory.mount.yaw_deg = 20.0;
  c.trajectory.mount.pitch_down_deg = 5.0;
  return c;
}

// Flight C (the merge tests): the same office, taking off at the far end of the room and facing
// the wall flight A never looks at (the UAV sweep, seed 4: it starts from the zone's +x end), then
// turning round during its forward flight into A's view (240 frames: the first 8 s of the sweep).
inline sim::SimConfig flight_c_config() {
  sim::SimConfig c = flight_a_config();
  c.seed = 4;
  c.trajectory.type = "uav_sweep";
  c.trajectory.frames = 240;
  return c;
}

inline std::string flight_dir(const sim::SimConfig& c, const std::string& name) {
  return cached_folder(std::filesystem::temp_directory_path() / ("s3m_it_session_" + name), "gt_voxels.txt",
                       [&](const std::filesystem::path& tmp) { sim::simulate_sequence(c, tmp.string()); });
}
inline const std::string& flight_a_dir() {
  static const std::string d = flight_dir(flight_a_config(), "office_l3_figure8_s3");
  return d;
}
inline const std::string& flight_b_dir() {
  static const std::string d = flight_dir(flight_b_config(), "office_l3_figure8_yaw20_s5");
  return d;
}

inline const std::string& flight_c_dir() {
  static const std::string d = flight_dir(flight_c_config(), "office_l3_sweep_s4");
  return d;
}

}  // namespace s3m::it
