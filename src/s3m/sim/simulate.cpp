#include "s3m/sim/simulate.hpp"

#include <cmath>
#include <exception>
#include <filesystem>
#include <thread>

#include "s3m/core/bounded_queue.hpp"
#include "s3m/core/classes.hpp"
#include "s3m/core/config_table.hpp"
#include "s3m/core/error.hpp"
#include "s3m/core/timing.hpp"
#include "s3m/core/yaml_util.hpp"
#include "s3m/io/atomic_file.hpp"
#include "s3m/io/trajectory.hpp"
#include "s3m/io/tum_dataset.hpp"
#include "s3m/sim/gt_voxels.hpp"
#include "s3m/sim/rng.hpp"

namespace s3m::sim {
namespace {

std::set<std::size_t> choose_dropped(int frames, int count, std::uint64_t seed) {
  std::set<std::size_t> out;
  Rng rng(seed ^ 0xD409ull);
  const int first = std::min(10, frames);
  while (static_cast<int>(out.size()) < std::min(count, frames - first))
    out.insert(static_cast<std::size_t>(rng.integer(first, frames - 1)));
  return out;
}

const SimConfig& validated(const SimConfig& c) {
  c.validate();
  return c;
}

io::Trajectory stamped(const Trajectory& t, bool robot) {
  io::Trajectory out;
  for (const auto& s : t.samples) out.push_back({s.t_s, robot ? s.T_w_r : s.T_w_c});
  return out;
}

void emit_pose(YAML::Emitter& e, const char* key, const SE3& T) {
  const Quat q(T.linear());
  e << YAML::Key << key << YAML::Value << YAML::BeginMap;
  e << YAML::Key << "t_m" << YAML::Value << YAML::Flow
    << std::vector<double>{T.translation().x(), T.translation().y(), T.translation().z()};
  e << YAML::Key << "q_xyzw" << YAML::Value << YAML::Flow << std::vector<double>{q.x(), q.y(), q.z(), q.w()};
  e << YAML::EndMap;
}

// sim.yaml: what produced the sequence, and the camera-to-robot calibration.
std::string sim_yaml(const SimConfig& c, const Trajectory& t, const SimSummary& s) {
  YAML::Emitter e;
  e.SetDoublePrecision(9);
  e << YAML::BeginMap;
  e << YAML::Key << "scene" << YAML::Value << c.scene << YAML::Key << "seed" << YAML::Value << c.seed;
  if (c.layout_seed) e << YAML::Key << "layout_seed" << YAML::Value << *c.layout_seed;  // absent: = seed
  e << YAML::Key << "trajectory" << YAML::Value << c.trajectory.type;
  e << YAML::Key << "frames" << YAML::Value << c.trajectory.frames << YAML::Key << "fps" << YAML::Value
    << c.trajectory.fps;
  e << YAML::Key << "drop_frames" << YAML::Value << c.drop_frames;
  e << YAML::Key << "noise" << YAML::Value << c.sensor.noise;
  e << YAML::Key << "voxel_resolution_m" << YAML::Value << c.voxel_resolution_m;
  e << YAML::Key << "trajectory_length_m" << YAML::Value << s.length_m;
  e << YAML::Key << "max_speed_mps" << YAML::Value << s.max_speed_mps;
  emit_pose(e, "T_c_r", t.T_c_r);
  e << YAML::EndMap;
  return std::string("# s3m simulated sequence; T_c_r maps robot-frame points into the camera frame\n") +
         e.c_str() + "\n";
}

}  // namespace

void SimConfig::validate() const {
  trajectory.validate();
  sensor.validate();
  require(drop_frames >= 0, "sim: drop_frames must be >= 0");
  require(voxel_resolution_m > 0.005 && voxel_resolution_m <= 1.0,
          "sim: voxel_resolution_m must be in (0.005, 1] m");
  make_scene(scene, layout());  // throws for an unknown preset
}

void fields(config::FieldVisitor& v, SimConfig& c) {
  v("scene", c.scene);
  v("seed", c.seed);
  std::optional<std::uint64_t>& layout = c.layout_seed;  // absent: the seed's
  v("layout_seed",
    config::Custom{[&layout](const YAML::Node& n, const std::string& key, const std::string& ctx) {
                     if (n.IsNull())
                       layout.reset();  // written as ~ when absent
                     else
                       layout = yaml_as<std::uint64_t>(n, key, ctx);
                   },
                   [&layout] { return layout ? YAML::Node(std::to_string(*layout)) : YAML::Node(); }});
  v("drop_frames", c.drop_frames);
  v("voxel_resolution_m", c.voxel_resolution_m);
  v("trajectory", c.trajectory);
  v("sensor", c.sensor);
}

void load_sim_config(const YAML::Node& n, SimConfig& c, const std::string& ctx) {
  config::read(n, config::table_of(c), ctx);
}

SimConfig load_sim_config(const std::string& path) {
  SimConfig c;
  load_sim_config(load_yaml_file(path), c, path);
  return c;
}

Simulation::Simulation(const SimConfig& cfg)
    : cfg_(validated(cfg)),
      renderer_(make_scene(cfg.scene, cfg.layout()), cfg.sensor),
      trajectory_(make_trajectory(renderer_.scene(), cfg.trajectory, cfg.seed)),
      dropped_(choose_dropped(cfg.trajectory.frames, cfg.drop_frames, cfg.seed)) {}

RgbdFrame Simulation::frame(std::size_t i) const {
  require(i < size(), "Simulation::frame: index " + std::to_string(i) + " out of range");
  const TrajectorySample& s = trajectory_.samples[i];
  RgbdFrame f;
  if (is_dropped(i)) {  // a dropped frame: the driver delivers a blank image pair
    const PinholeCamera& c = camera();
    f.rgb = cv::Mat::zeros(c.height, c.width, CV_8UC3);
    f.depth_m = cv::Mat::zeros(c.height, c.width, CV_32FC1);
    f.labels = cv::Mat::zeros(c.height, c.width, CV_16UC1);
  } else {
    const SE3 T_open =
        i > 0 ? interpolate(trajectory_.samples[i - 1].T_w_c, s.T_w_c,
                            std::clamp(1.0 - cfg_.sensor.exposure_s * cfg_.trajectory.fps, 0.0, 1.0))
              : s.T_w_c;
    f = renderer_.render(s.T_w_c, hash3(cfg_.seed, i, 0xF4A3Eull), &T_open);
  }
  f.index = static_cast<int>(i);
  f.t_s = s.t_s;
  return f;
}

SimSummary simulate_sequence(const SimConfig& cfg, const std::string& out_dir,
                             const std::function<void(int, int)>& progress) {
  Stopwatch total;
  // 1. Scene, trajectory, renderer.
  const Simulation sim(cfg);
  SimSummary sum;
  sum.frames = static_cast<int>(sim.size());
  sum.max_speed_mps = sim.trajectory().max_speed_mps();
  sum.length_m = sim.trajectory().length_m();
  std::filesystem::create_directories(out_dir);
  // 2. Render frames here; a writer thread encodes PNGs, fed through a bounded queue.
  io::TumWriter writer(out_dir, sim.camera());
  BoundedQueue<std::pair<RgbdFrame, SE3>> queue(4);
  std::exception_ptr writer_error;
  std::thread writer_thread([&] {
    try {
      while (auto item = queue.pop()) writer.add(item->first, item->second);
    } catch (...) {
      writer_error = std::current_exception();
      queue.close();
    }
  });
  double render_ms = 0;
  try {
    for (std::size_t i = 0; i < sim.size(); ++i) {
      Stopwatch sw;
      RgbdFrame f = sim.frame(i);
      render_ms += sw.elapsed_ms();
      sum.dropped += sim.is_dropped(i) ? 1 : 0;
      if (!queue.push({std::move(f), sim.trajectory().samples[i].T_w_c})) break;
      if (progress) progress(static_cast<int>(i) + 1, sum.frames);
    }
  } catch (...) {
    queue.close();
    writer_thread.join();
    throw;
  }
  queue.close();
  writer_thread.join();
  if (writer_error) std::rethrow_exception(writer_error);
  writer.finish();  // list files, groundtruth.txt (camera), camera.yaml
  // 3. Robot ground truth, class list, ground-truth voxel map, provenance.
  const std::filesystem::path d(out_dir);
  io::write_tum_trajectory((d / "groundtruth_robot.txt").string(), stamped(sim.trajectory(), true));
  write_class_list((d / "classes.txt").string(), indoor_classes());
  const io::GtVoxelMap voxels = voxelize_scene(sim.scene(), cfg.voxel_resolution_m);
  io::write_gt_voxels((d / "gt_voxels.txt").string(), voxels);
  sum.voxels = voxels.labels.size();
  sum.render_ms_mean = sum.frames ? render_ms / sum.frames : 0.0;
  io::write_text_atomic((d / "sim.yaml").string(), sim_yaml(cfg, sim.trajectory(), sum));
  sum.seconds = total.elapsed_ms() / 1000.0;
  return sum;
}

}  // namespace s3m::sim
