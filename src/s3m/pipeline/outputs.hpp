#pragma once
// Writing a run's products into OUT: trajectories (camera, robot), keyframes, the semantic map
// (.ot with full semantics, .ply). Every file is written atomically (temp file + rename), so an
// interrupted or failing run never leaves a half-written file behind.
#include <string>

#include "s3m/io/trajectory.hpp"
#include "s3m/pipeline/pipeline.hpp"

namespace s3m::pipeline {

struct OutputPaths {
  std::string out_dir;
  std::string trajectory_camera, trajectory_robot, keyframes;  // TUM format
  std::string map_ot, map_ply;                                 // empty when there is no map
  std::string metrics;
};

// T_w_r = T_w_c * T_c_r for every pose (the paper's camera-to-robot calibration).
io::Trajectory robot_trajectory(const io::Trajectory& camera, const SE3& T_c_r);

OutputPaths write_outputs(const Pipeline& pipeline, const PipelineConfig& config, const std::string& out_dir);

}  // namespace s3m::pipeline
