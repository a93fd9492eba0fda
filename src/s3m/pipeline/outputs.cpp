#include "s3m/pipeline/outputs.hpp"

#include <filesystem>

#include <spdlog/spdlog.h>

namespace s3m::pipeline {

io::Trajectory robot_trajectory(const io::Trajectory& camera, const SE3& T_c_r) {
  io::Trajectory out;
  out.reserve(camera.size());
  for (const auto& p : camera) out.push_back({p.t_s, p.T_w_x * T_c_r});
  return out;
}

OutputPaths write_outputs(const Pipeline& pipeline, const PipelineConfig& config, const std::string& out_dir) {
  std::filesystem::create_directories(out_dir);
  OutputPaths p;
  p.out_dir = out_dir;
  p.trajectory_camera = out_dir + "/trajectory_camera.txt";
  p.trajectory_robot = out_dir + "/trajectory_robot.txt";
  p.keyframes = out_dir + "/keyframes.txt";
  p.metrics = out_dir + "/metrics.json";
  const io::Trajectory cam = pipeline.poses().camera_trajectory();
  if (cam.empty()) spdlog::warn("outputs: no frame was tracked; trajectory files are empty");
  io::write_tum_trajectory(p.trajectory_camera, cam);
  io::write_tum_trajectory(p.trajectory_robot, robot_trajectory(cam, config.slam.T_c_r));
  io::write_tum_trajectory(p.keyframes, pipeline.poses().keyframe_trajectory());
  if (const MapIntegrator* map = pipeline.map()) {
    p.map_ot = out_dir + "/map.ot";
    p.map_ply = out_dir + "/map.ply";
    map->save(p.map_ot, p.map_ply);
  }
  return p;
}

}  // namespace s3m::pipeline
