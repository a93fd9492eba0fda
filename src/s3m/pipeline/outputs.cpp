#include "s3m/pipeline/outputs.hpp"

#include <cstdio>
#include <filesystem>
#include <vector>

#include <spdlog/spdlog.h>

#include "s3m/core/error.hpp"
#include "s3m/io/atomic_file.hpp"
#include "s3m/pipeline/session_io.hpp"

namespace s3m::pipeline {

io::Trajectory robot_trajectory(const io::Trajectory& camera, const SE3& T_c_r) {
  io::Trajectory out;
  out.reserve(camera.size());
  for (const auto& p : camera) out.push_back({p.t_s, robot_pose(p.T_w_x, T_c_r)});
  return out;
}

std::string frames_table(const std::vector<FrameOutcome>& frames) {
  std::string out = "# index t_s state tracked keyframe integrated\n";
  char line[160];
  for (const FrameOutcome& f : frames) {
    std::snprintf(line, sizeof line, "%d %.6f %s %d %d %d\n", f.index, f.t_s, to_string(f.state),
                  int(f.tracked), int(f.keyframe), int(f.integrated));
    out += line;
  }
  return out;
}

namespace {

// Products of an earlier run in the same folder that this run did not make (a --slam-only run after
// a full one: its map.ot beside the new trajectory) would be read as this run's: they go.
void remove_stale_outputs(const OutputPaths& p, bool session_written) {
  const std::string dir = p.out_dir;
  std::vector<std::string> stale;
  if (p.map_ot.empty()) stale.insert(stale.end(), {dir + "/map.ot", dir + "/map.ply"});
  if (session_written && p.slam_map.empty()) stale.push_back(dir + "/" + kSlamMapFile);
  if (session_written && p.kept_clouds.empty()) stale.push_back(dir + "/" + kKeptCloudsFile);
  for (const std::string& f : stale) {
    std::error_code ec;
    if (std::filesystem::remove(f, ec))
      spdlog::info("outputs: removed {} of an earlier run (not made by this one)", f);
  }
}

}  // namespace

OutputPaths write_outputs(const Pipeline& pipeline, const PipelineConfig& config, const std::string& out_dir,
                          bool write_session) {
  std::error_code ec;
  std::filesystem::create_directories(out_dir, ec);
  if (ec) throw Error("outputs: cannot create '" + out_dir + "': " + ec.message());
  OutputPaths p;
  p.out_dir = out_dir;
  p.trajectory_camera = out_dir + "/trajectory_camera.txt";
  p.trajectory_robot = out_dir + "/trajectory_robot.txt";
  p.keyframes = out_dir + "/keyframes.txt";
  p.metrics = out_dir + "/metrics.json";
  p.frames = out_dir + "/frames.txt";
  const io::Trajectory cam = pipeline.poses().camera_trajectory();
  if (cam.empty()) spdlog::warn("outputs: no frame was tracked; trajectory files are empty");
  io::write_tum_trajectory(p.trajectory_camera, cam);
  io::write_tum_trajectory(p.trajectory_robot, robot_trajectory(cam, config.slam.T_c_r));
  io::write_tum_trajectory(p.keyframes, pipeline.poses().keyframe_trajectory());
  io::write_text_atomic(p.frames, frames_table(pipeline.frames()));
  if (const MapIntegrator* map = pipeline.map()) {
    p.map_ot = out_dir + "/map.ot";
    p.map_ply = out_dir + "/map.ply";
    map->save(p.map_ot, p.map_ply);
  }
  if (write_session) {
    const SessionMap* session = pipeline.poses().session_map();
    if (session && session->save_map(out_dir + "/" + kSlamMapFile)) p.slam_map = out_dir + "/" + kSlamMapFile;
    if (pipeline.map() && !p.slam_map.empty()) {
      p.kept_clouds = out_dir + "/" + kKeptCloudsFile;
      save_kept_clouds(p.kept_clouds, pipeline.keyframe_store());
    }
  }
  remove_stale_outputs(p, write_session);
  return p;
}

}  // namespace s3m::pipeline
