#pragma once
// In-process simulation API and the TUM-layout sequence writer behind `s3m sim`.
//
//   sim::SimConfig cfg;                       // defaults: office, uav_sweep, 300 frames, seed 7
//   sim::Simulation sim(cfg);                 // scene + trajectory + renderer
//   RgbdFrame f = sim.frame(i);               // rgb, depth_m, labels, t_s, index
//   SE3 T_w_c = sim.trajectory().samples[i].T_w_c;
//   sim::simulate_sequence(cfg, "out/");      // rgb/ depth/ labels/ *.txt camera.yaml classes.txt
//   gt_voxels.txt
#include <cstdint>
#include <functional>
#include <optional>
#include <set>
#include <string>

#include "s3m/core/rgbd_frame.hpp"
#include "s3m/io/gt_voxels.hpp"
#include "s3m/sim/people.hpp"
#include "s3m/sim/renderer.hpp"
#include "s3m/sim/scene.hpp"
#include "s3m/sim/sensor.hpp"
#include "s3m/sim/trajectory.hpp"

namespace s3m::config {
class FieldVisitor;
}

namespace s3m::sim {

struct SimConfig {
  std::string scene = "office";  // preset name, see scene_presets()
  std::uint64_t seed = 7;        // trajectory variation, dropped frames and sensor noise (and the
                                 // layout unless layout_seed is set)
  // Scene layout (positions, sizes, colours, patterns). Unset: the layout follows `seed`, so
  // sequences made before layout_seed existed stay byte-identical. Two configs with the same
  // layout_seed and different seeds fly through one and the same building.
  std::optional<std::uint64_t> layout_seed;
  TrajectoryConfig trajectory;
  SensorConfig sensor;
  PeopleConfig people;               // people walking through (none by default)
  int drop_frames = 0;               // this many frames (never the first 10) come out blank: black, no depth
  double voxel_resolution_m = 0.05;  // ground-truth voxel map resolution
  std::uint64_t layout() const { return layout_seed.value_or(seed); }
  void validate() const;
};

// YAML keys: scene, seed, layout_seed, drop_frames, voxel_resolution_m, trajectory: {...}, sensor: {...},
// people: {...}.
// Unknown keys are errors (ParseError with file and line).
SimConfig load_sim_config(const std::string& path);
void load_sim_config(const YAML::Node& node, SimConfig& cfg, const std::string& ctx);
// Its YAML keys with the members they fill (core/config_table.hpp).
void fields(config::FieldVisitor& v, SimConfig& c);

class Simulation {
 public:
  explicit Simulation(const SimConfig& cfg);

  std::size_t size() const { return trajectory_.samples.size(); }
  const SimConfig& config() const { return cfg_; }
  const Scene& scene() const { return renderer_.scene(); }
  const Trajectory& trajectory() const { return trajectory_; }
  const Renderer& renderer() const { return renderer_; }
  const PinholeCamera& camera() const { return renderer_.camera(); }
  bool is_dropped(std::size_t i) const { return dropped_.count(i) > 0; }
  const std::vector<Walker>& walkers() const { return walkers_; }

  // Frame i as the sensor delivers it (noise per config; blank if dropped); t_s is its colour
  // stamp. With people, dynamic_mask marks the pixels that see one (all zero when dropped).
  // Thread-safe.
  RgbdFrame frame(std::size_t i) const;
  // Frame i's capture instants [s]: the trajectory sample's time, unless the sensor's timing lies
  // (offset, jitter) move them; jitter is drawn per seed and frame.
  FrameTimes frame_times(std::size_t i) const;
  // The colour camera's pose at frame i's colour stamp (groundtruth.txt).
  SE3 T_w_c(std::size_t i) const;

 private:
  SimConfig cfg_;
  Renderer renderer_;
  Trajectory trajectory_;
  std::set<std::size_t> dropped_;
  std::vector<Walker> walkers_;  // people, planned per seed (empty: a static scene)
};

struct SimSummary {
  int frames = 0;
  int dropped = 0;
  std::size_t voxels = 0;
  double seconds = 0;         // wall time of the whole run
  double render_ms_mean = 0;  // per frame, sensor model included, PNG writing excluded
  double max_speed_mps = 0;
  double length_m = 0;
};

// Renders the whole sequence into out_dir (created if needed) in TUM layout:
// rgb/ depth/ labels/ rgb.txt depth.txt labels.txt associations.txt groundtruth.txt (T_w_c)
// groundtruth_robot.txt (T_w_r) camera.yaml classes.txt gt_voxels.txt sim.yaml (config + T_c_r).
// With people: dynamic/<frame index, 6 digits>.png (255 where a person is seen) and people.txt
// (`frame t_s person x y` per person and frame: where each stands on the floor); gt_voxels.txt
// stays the static scene's.
// progress(done, total) is called after each frame. Same config -> byte-identical files.
SimSummary simulate_sequence(const SimConfig& cfg, const std::string& out_dir,
                             const std::function<void(int, int)>& progress = {});

}  // namespace s3m::sim
