#include "s3m/sim/simulate.hpp"

#include <cmath>
#include <cstdio>
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
#include "s3m/io/image_io.hpp"
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

// A stream's capture instant minus its nominal one [s]: Gaussian, bounded to 3 sigma so that the
// stamps of each stream stay in order (SimConfig::validate).
double jitter_s(std::uint64_t seed, std::size_t frame, std::uint64_t stream, double sigma) {
  if (sigma <= 0) return 0.0;
  const double n = gaussian(hash3(seed, frame, stream), hash3(seed, frame, stream + 1));
  return sigma * std::clamp(n, -3.0, 3.0);
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

// The true values of the sensor's lies, for whoever estimates them from the data; nothing when all
// are off (sequences without them stay as they were).
void emit_sensor_lies(YAML::Emitter& e, const SensorConfig& s) {
  if (!s.timed() && s.disparity_step_px == 0 && s.edge_fattening_px == 0) return;
  e << YAML::Key << "sensor_lies" << YAML::Value << YAML::BeginMap;
  e << YAML::Key << "depth_time_offset_s" << YAML::Value << s.depth_time_offset_s;
  e << YAML::Key << "time_jitter_s" << YAML::Value << s.time_jitter_s;
  e << YAML::Key << "rolling_shutter_s" << YAML::Value << s.camera.rolling_shutter_s;
  e << YAML::Key << "motion_blur_samples" << YAML::Value << s.motion_blur_samples;
  e << YAML::Key << "exposure_s" << YAML::Value << s.exposure_s;
  e << YAML::Key << "disparity_step_px" << YAML::Value << s.disparity_step_px;
  e << YAML::Key << "disparity_baseline_m" << YAML::Value << s.disparity_baseline_m;
  e << YAML::Key << "edge_fattening_px" << YAML::Value << s.edge_fattening_px;
  e << YAML::Key << "depth_registration_error_px" << YAML::Value << s.depth_registration_error_px;
  e << YAML::Key << "depth_sigma0_m" << YAML::Value << s.depth_sigma0_m;
  e << YAML::Key << "depth_sigma_k" << YAML::Value << s.depth_sigma_k;
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
  if (c.people.count > 0) e << YAML::Key << "people" << YAML::Value << c.people.count;  // absent: none
  e << YAML::Key << "trajectory_length_m" << YAML::Value << s.length_m;
  e << YAML::Key << "max_speed_mps" << YAML::Value << s.max_speed_mps;
  emit_pose(e, "T_c_r", t.T_c_r);
  emit_sensor_lies(e, c.sensor);
  e << YAML::EndMap;
  return std::string("# s3m simulated sequence; T_c_r maps robot-frame points into the camera frame\n") +
         e.c_str() + "\n";
}

// dynamic/<index>.png: the frame's ground-truth mask of what moves.
void write_dynamic_mask(const std::string& out_dir, const RgbdFrame& f) {
  char name[32];
  std::snprintf(name, sizeof(name), "%06d.png", f.index);
  const std::filesystem::path dir = std::filesystem::path(out_dir) / "dynamic";
  std::filesystem::create_directories(dir);
  io::write_label_png((dir / name).string(), f.dynamic_mask);
}

// people.txt: where each person stands at each frame's colour stamp.
std::string people_table(const Simulation& sim) {
  std::string out = "# frame t_s person x_m y_m (floor position, world frame)\n";
  char line[128];
  for (std::size_t i = 0; i < sim.size(); ++i) {
    const double t = sim.frame_times(i).colour_s;
    for (std::size_t k = 0; k < sim.walkers().size(); ++k) {
      const Eigen::Vector2d p = sim.walkers()[k].position(t);
      std::snprintf(line, sizeof(line), "%zu %.6f %zu %.4f %.4f\n", i, t, k, p.x(), p.y());
      out += line;
    }
  }
  return out;
}

}  // namespace

void SimConfig::validate() const {
  trajectory.validate();
  sensor.validate();
  people.validate();
  require(drop_frames >= 0, "sim: drop_frames must be >= 0");
  require(6.0 * sensor.time_jitter_s < 1.0 / trajectory.fps,
          "sim: sensor.time_jitter_s must be below 1 / (6 fps), or a stream's stamps could swap order");
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
  v("people", c.people);
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
      dropped_(choose_dropped(cfg.trajectory.frames, cfg.drop_frames, cfg.seed)),
      walkers_(plan_walkers(renderer_.scene(), trajectory_, cfg.people, cfg.seed)) {}

RgbdFrame Simulation::frame(std::size_t i) const {
  require(i < size(), "Simulation::frame: index " + std::to_string(i) + " out of range");
  const TrajectorySample& s = trajectory_.samples[i];
  RgbdFrame f;
  if (is_dropped(i)) {  // a dropped frame: the driver delivers a blank image pair
    const PinholeCamera& c = camera();
    f.rgb = cv::Mat::zeros(c.height, c.width, CV_8UC3);
    f.depth_m = cv::Mat::zeros(c.height, c.width, CV_32FC1);
    f.labels = cv::Mat::zeros(c.height, c.width, CV_16UC1);
    if (!walkers_.empty()) f.dynamic_mask = cv::Mat::zeros(c.height, c.width, CV_8UC1);
    f.index = static_cast<int>(i);
    f.t_s = frame_times(i).colour_s;
    return f;
  }
  // People where they are at the colour stamp.
  std::optional<MovingLayer> people;
  if (!walkers_.empty()) {
    std::vector<Primitive> prims;
    for (const Walker& w : walkers_)
      for (Primitive& p : walker_primitives(w, frame_times(i).colour_s)) prims.push_back(std::move(p));
    people.emplace(std::move(prims));
  }
  const MovingLayer* movers = people ? &*people : nullptr;
  if (cfg_.sensor.timed()) {  // parts of the frame at other instants: the continuous path
    f = renderer_.render_timed([this](double t) { return trajectory_.T_w_c_at(t); }, frame_times(i),
                               hash3(cfg_.seed, i, 0xF4A3Eull), movers);
  } else {
    const SE3 T_open =
        i > 0 ? interpolate(trajectory_.samples[i - 1].T_w_c, s.T_w_c,
                            std::clamp(1.0 - cfg_.sensor.exposure_s * cfg_.trajectory.fps, 0.0, 1.0))
              : s.T_w_c;
    f = renderer_.render(s.T_w_c, hash3(cfg_.seed, i, 0xF4A3Eull), &T_open, movers);
  }
  f.index = static_cast<int>(i);
  f.t_s = frame_times(i).colour_s;
  return f;
}

FrameTimes Simulation::frame_times(std::size_t i) const {
  const double t = trajectory_.samples.at(i).t_s;
  if (!cfg_.sensor.timed()) return {t, t};
  const SensorConfig& s = cfg_.sensor;
  return {t + jitter_s(cfg_.seed, i, 0xC0107ull, s.time_jitter_s),
          t + s.depth_time_offset_s + jitter_s(cfg_.seed, i, 0xDE97ull, s.time_jitter_s)};
}

SE3 Simulation::T_w_c(std::size_t i) const {
  return cfg_.sensor.timed() ? trajectory_.T_w_c_at(frame_times(i).colour_s)
                             : trajectory_.samples.at(i).T_w_c;
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
  struct Stamped {  // what the writer needs beside the images: ground truth and the depth stamp
    SE3 T_w_c;
    double depth_t_s;
  };
  BoundedQueue<std::pair<RgbdFrame, Stamped>> queue(4);
  std::exception_ptr writer_error;
  std::thread writer_thread([&] {
    try {
      while (auto item = queue.pop()) {
        writer.add(item->first, item->second.T_w_c, item->second.depth_t_s);
        if (!item->first.dynamic_mask.empty()) write_dynamic_mask(out_dir, item->first);
      }
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
      if (!queue.push({std::move(f), {sim.T_w_c(i), sim.frame_times(i).depth_s}})) break;
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
  if (!sim.walkers().empty()) io::write_text_atomic((d / "people.txt").string(), people_table(sim));
  io::write_text_atomic((d / "sim.yaml").string(), sim_yaml(cfg, sim.trajectory(), sum));
  sum.seconds = total.elapsed_ms() / 1000.0;
  return sum;
}

}  // namespace s3m::sim
