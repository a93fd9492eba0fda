// `s3m sim`: render a synthetic RGB-D sequence with ground truth (see s3m/sim/simulate.hpp).
#include <algorithm>
#include <cctype>
#include <cstdio>
#include <filesystem>
#include <sstream>
#include <vector>

#include <fmt/format.h>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include "commands.hpp"
#include "s3m/core/error.hpp"
#include "s3m/core/timing.hpp"
#include "s3m/io/output_folder.hpp"
#include "s3m/sim/simulate.hpp"

namespace s3m::apps {
namespace {

struct SimArgs {
  std::string config_path, out_dir, scene = "office", trajectory = "uav_sweep", camera = "kinect", snapshots,
                                    sensor_profile;
  int frames = 300, width = 640, height = 480, drop_frames = 0, motion_blur = 1, people = 0;
  double depth_time_offset_s = 0.0;
  std::uint64_t seed = 7, layout_seed = 0;
  double fps = 30.0, voxel_res_m = 0.05;
  bool noise = true, snapshots_only = false, force = false;
};

// A folder holding a recording that s3m sim did not make (its lists without a sim.yaml): rendering
// into it would replace the recording's lists and camera.yaml.
void refuse_recording(const std::string& out_dir, bool force) {
  namespace fs = std::filesystem;
  std::error_code ec;
  if (force || !fs::exists(fs::path(out_dir) / "rgb.txt", ec) ||
      fs::exists(fs::path(out_dir) / "sim.yaml", ec))
    return;
  throw Error("--out '" + out_dir +
              "' holds a recording (rgb.txt, no sim.yaml): s3m sim would replace its lists and camera.yaml; "
              "give another folder, or --force to write over it");
}

// A sequence no one means (--frames 2000000000) is refused before the work with its estimate: it would
// fill the disk after hours, with the trajectory alone outgrowing memory first. The constants are
// measured: colour, depth and label PNGs of the simulator take ~3.3 bytes a pixel, rendering ~0.3 us
// a pixel on one core.
void check_sim_cost(const sim::SimConfig& cfg, const std::string& out_dir, bool force) {
  namespace fs = std::filesystem;
  constexpr double kBytesPerPixel = 3.3, kSecondsPerPixel = 0.3e-6, kMaxGb = 20.0, kMaxHours = 2.0;
  const double pixels = double(cfg.trajectory.frames) * cfg.sensor.camera.width * cfg.sensor.camera.height;
  const double gb = pixels * kBytesPerPixel / 1e9, hours = pixels * kSecondsPerPixel / 3600.0;
  std::error_code ec;
  fs::path existing = fs::absolute(out_dir, ec);
  while (!existing.empty() && !fs::exists(existing, ec) && existing != existing.parent_path())
    existing = existing.parent_path();
  const fs::space_info space = fs::space(existing, ec);
  const double free_gb = ec ? -1.0 : double(space.available) / 1e9;
  const std::string what =
      fmt::format("{} frames of {}x{} px would take ~{:.1f} GB of disk and ~{:.1f} h", cfg.trajectory.frames,
                  cfg.sensor.camera.width, cfg.sensor.camera.height, gb, hours);
  if (force) return;
  if (free_gb >= 0 && gb > free_gb)
    throw Error(
        fmt::format("sim: {}; {} has {:.1f} GB free: fewer --frames or a smaller --width/--height, or "
                    "--force to go on",
                    what, existing.string(), free_gb));
  if (gb <= kMaxGb && hours <= kMaxHours) return;
  throw Error(
      fmt::format("sim: {} (limits {:.0f} GB, {:.0f} h): fewer --frames or a smaller --width/--height, "
                  "or --force to go on",
                  what, kMaxGb, kMaxHours));
}

// A strip naming the classes present in a label image, with their palette colours.
cv::Mat label_legend(const cv::Mat& labels, int width) {
  cv::Mat strip(36, width, CV_8UC3, cv::Scalar(255, 255, 255));
  int x = 8;
  for (const ClassInfo& c : indoor_classes().all()) {
    if (c.id == cls::kUnknown || cv::countNonZero(labels == c.id) == 0) continue;
    cv::rectangle(strip, cv::Rect(x, 9, 18, 18), cv::Scalar(c.b, c.g, c.r), cv::FILLED);
    cv::putText(strip, c.name, {x + 24, 24}, cv::FONT_HERSHEY_SIMPLEX, 0.55, cv::Scalar(0, 0, 0), 1,
                cv::LINE_AA);
    x += 24 + 11 * static_cast<int>(c.name.size()) + 18;
  }
  return strip;
}

// One picture per requested frame: colour | depth (turbo, 0-5 m, black = missing) | labels, and a legend.
// "0,120,240" -> the frame numbers; anything else is refused naming the item.
std::vector<int> snapshot_frames(const std::string& list, std::size_t frames) {
  std::vector<int> out;
  std::stringstream ss(list);
  std::string item;
  while (std::getline(ss, item, ',')) {
    const bool digits =
        !item.empty() && item.size() <= 9 &&
        std::all_of(item.begin(), item.end(), [](unsigned char c) { return std::isdigit(c); });
    require(digits, "--snapshots: '" + item + "' is not a frame number (expected e.g. 0,120,240)");
    out.push_back(std::stoi(item));
    require(std::size_t(out.back()) < frames, "--snapshots: frame " + item + " is outside the sequence (" +
                                                  std::to_string(frames) + " frames)");
  }
  return out;
}

void write_snapshots(const sim::SimConfig& cfg, const std::string& list, const std::string& out_dir) {
  const sim::Simulation sim(cfg);
  const std::vector<int> frames = snapshot_frames(list, sim.size());
  std::filesystem::create_directories(std::filesystem::path(out_dir) / "snapshots");
  for (const int i : frames) {
    const std::string item = std::to_string(i);
    const RgbdFrame f = sim.frame(i);
    cv::Mat row;
    cv::hconcat(
        std::vector<cv::Mat>{f.rgb, sim::colourise_depth(f.depth_m, 5.0), sim::colourise_labels(f.labels)},
        row);
    cv::vconcat(row, label_legend(f.labels, row.cols), row);
    const std::string path =
        (std::filesystem::path(out_dir) / "snapshots" / ("frame_" + item + ".png")).string();
    if (!cv::imwrite(path, row)) throw Error("cannot write " + path);
  }
}

void run(const SimArgs& a, const CLI::App& cmd) {
  sim::SimConfig cfg = a.config_path.empty() ? sim::SimConfig{} : sim::load_sim_config(a.config_path);
  // Command-line options override the config file only when given explicitly.
  auto given = [&](const char* name) { return a.config_path.empty() || cmd.count(name) > 0; };
  if (given("--scene")) cfg.scene = a.scene;
  if (given("--seed")) cfg.seed = a.seed;
  if (cmd.count("--layout-seed")) cfg.layout_seed = a.layout_seed;
  if (given("--trajectory")) cfg.trajectory.type = a.trajectory;
  if (given("--frames")) cfg.trajectory.frames = a.frames;
  if (given("--fps")) cfg.trajectory.fps = a.fps;
  if (given("--drop-frames")) cfg.drop_frames = a.drop_frames;
  if (given("--people")) cfg.people.count = a.people;
  if (given("--voxel-res")) cfg.voxel_resolution_m = a.voxel_res_m;
  if (given("--camera") || given("--width") || given("--height")) {
    const double readout = cfg.sensor.camera.rolling_shutter_s;  // the shutter's, not the lens's
    cfg.sensor.camera = sim::sensor_camera(a.camera, a.width, a.height);
    cfg.sensor.camera.rolling_shutter_s = readout;
  }
  // A profile sets noise and motion blur itself; only options written out override it then.
  if (!a.sensor_profile.empty()) sim::apply_sensor_profile(a.sensor_profile, cfg.sensor);
  auto sensor_given = [&](const char* name) {
    return a.sensor_profile.empty() ? given(name) : cmd.count(name) > 0;
  };
  if (sensor_given("--motion-blur")) cfg.sensor.motion_blur_samples = a.motion_blur;
  if (sensor_given("--noise") || cmd.count("--no-noise")) cfg.sensor.noise = a.noise;
  if (cmd.count("--depth-time-offset")) cfg.sensor.depth_time_offset_s = a.depth_time_offset_s;
  cfg.validate();
  io::require_folder_path(a.out_dir, "--out");
  refuse_recording(a.out_dir, a.force);
  if (!a.snapshots_only) check_sim_cost(cfg, a.out_dir, a.force);
  if (!a.snapshots.empty())
    snapshot_frames(a.snapshots, std::size_t(cfg.trajectory.frames));  // before the work

  if (a.snapshots_only) {
    require(!a.snapshots.empty(), "--snapshots-only needs --snapshots");
    write_snapshots(cfg, a.snapshots, a.out_dir);
    std::fprintf(stderr, "s3m sim: wrote snapshots %s to %s/snapshots\n", a.snapshots.c_str(),
                 a.out_dir.c_str());
    return;
  }
  std::fprintf(stderr,
               "s3m sim: scene %s (layout seed %llu, seed %llu), trajectory %s, %d frames at %dx%d -> %s\n",
               cfg.scene.c_str(), static_cast<unsigned long long>(cfg.layout()),
               static_cast<unsigned long long>(cfg.seed), cfg.trajectory.type.c_str(), cfg.trajectory.frames,
               cfg.sensor.camera.width, cfg.sensor.camera.height, a.out_dir.c_str());
  Stopwatch sw;
  // Staged: a simulation that fails halfway (a full disk) leaves the folder as it was, and a longer
  // earlier sequence's frames do not stay beside a shorter new one.
  io::StagedFolder out(a.out_dir, "--out");
  const sim::SimSummary s = sim::simulate_sequence(cfg, out.path(), [&](int done, int total) {
    const double fps = done / std::max(1e-3, sw.elapsed_ms() / 1000.0);
    std::fprintf(stderr, "\r  frame %d/%d  %.1f frames/s  ETA %.0f s   ", done, total, fps,
                 (total - done) / fps);
    std::fflush(stderr);
  });
  out.commit({"rgb", "depth", "labels", "rgb.txt", "depth.txt", "labels.txt", "associations.txt",
              "camera.yaml", "classes.txt", "groundtruth.txt", "groundtruth_robot.txt", "gt_voxels.txt",
              "sim.yaml", "dynamic", "people.txt"});
  std::fprintf(
      stderr,
      "\ndone: %d frames (%d dropped) in %.1f s, %.1f ms/frame rendering; trajectory %.2f m, max speed "
      "%.2f m/s; %zu ground-truth voxels at %.3f m\n",
      s.frames, s.dropped, s.seconds, s.render_ms_mean, s.length_m, s.max_speed_mps, s.voxels,
      cfg.voxel_resolution_m);
  if (!a.snapshots.empty()) write_snapshots(cfg, a.snapshots, a.out_dir);
}

}  // namespace

void register_sim(CLI::App& app) {
  auto args = std::make_shared<SimArgs>();
  auto* cmd = app.add_subcommand(
      "sim", "Render a synthetic indoor RGB-D sequence with ground-truth poses and labels");
  cmd->add_option("--out,-o", args->out_dir, "Output directory (TUM layout)")->required();
  cmd->add_option("--config", args->config_path,
                  "YAML config (see config/sim_*.yaml); options below override it")
      ->check(CLI::ExistingFile);
  cmd->add_option("--scene", args->scene, "Scene preset: office, living_room, corridor")
      ->capture_default_str();
  cmd->add_option("--trajectory", args->trajectory,
                  "uav_sweep, figure8, loop, lawnmower, handheld, handheld_pan, hover, forward")
      ->capture_default_str();
  cmd->add_option("--frames", args->frames, "Number of frames")->capture_default_str();
  cmd->add_option("--fps", args->fps, "Frame rate [Hz]")->capture_default_str();
  cmd->add_option("--seed", args->seed,
                  "Seed for trajectory variation and noise (and the layout without --layout-seed)")
      ->capture_default_str();
  cmd->add_option(
      "--layout-seed", args->layout_seed,
      "Seed for the scene layout only (default: --seed); same value = same building, other flights");
  cmd->add_option("--camera", args->camera, "Intrinsics: kinect (fx 525 at 640 px) or d455 (fx 382.6)")
      ->capture_default_str();
  cmd->add_option("--width", args->width, "Image width [px]")->capture_default_str();
  cmd->add_option("--height", args->height, "Image height [px]")->capture_default_str();
  cmd->add_flag("--noise,!--no-noise", args->noise, "Sensor noise and dropouts on/off (default on)");
  cmd->add_option("--people", args->people,
                  "People walking through the scene (capsules labelled person; masks in dynamic/, paths in "
                  "people.txt)")
      ->check(CLI::Range(0, 20));
  cmd->add_option("--drop-frames", args->drop_frames, "Number of blank (dropped) frames")
      ->capture_default_str();
  cmd->add_option("--motion-blur", args->motion_blur, "Motion blur samples per frame (1 = off)")
      ->capture_default_str();
  cmd->add_option(
         "--sensor-profile", args->sensor_profile,
         "Sensor mix over the config's sensor: default (noise, no lies), ideal (no noise) or realistic "
         "(Kinect v1: colour-depth offset, jitter, rolling shutter, motion blur, disparity steps, "
         "edge fattening, misregistration); --noise / --motion-blur given as well override it")
      ->check(CLI::IsMember(sim::sensor_profiles()));
  cmd->add_option("--depth-time-offset", args->depth_time_offset_s,
                  "Depth captured this many seconds after colour (sensor.depth_time_offset_s; < 0: before)");
  cmd->add_option("--voxel-res", args->voxel_res_m, "Ground-truth voxel map resolution [m]")
      ->capture_default_str();
  cmd->add_option("--snapshots", args->snapshots,
                  "Comma-separated frame indices to save as rgb|depth|labels PNGs");
  cmd->add_flag("--snapshots-only", args->snapshots_only, "Only write the --snapshots pictures, no sequence");
  cmd->add_flag("--force", args->force,
                "Write into an --out folder that holds a recording not made by s3m sim, and render a "
                "sequence over the size limits (20 GB, 2 h estimated)");
  cmd->callback([args, cmd] { run(*args, *cmd); });
}

}  // namespace s3m::apps
