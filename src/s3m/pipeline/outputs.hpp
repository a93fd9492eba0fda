#pragma once
// Writing a run's products into OUT: trajectories (camera, robot), keyframes, the per-frame tracking
// states (frames.txt), the semantic map (.ot with full semantics, .ply). Every file is written atomically
// (temp file + rename), so an interrupted or failing run never leaves a half-written file behind.
#include <string>

#include "s3m/io/trajectory.hpp"
#include "s3m/pipeline/pipeline.hpp"

namespace s3m::pipeline {

struct OutputPaths {
  std::string out_dir;
  std::string trajectory_camera, trajectory_robot, keyframes;  // TUM format
  std::string frames;                                          // one line per frame: its tracking state
  std::string map_ot, map_ply;                                 // empty when there is no map
  std::string slam_map, kept_clouds;  // the session (session_io.hpp); empty: not written
  std::string metrics;
  std::string config_effective;  // the settings in effect (run/effective_config.hpp); written by run_dataset
};

// robot_pose(T_w_c, T_c_r) = T_w_c * T_c_r for every pose (core/se3.hpp).
io::Trajectory robot_trajectory(const io::Trajectory& camera, const SE3& T_c_r);

// frames.txt: "index t_s state tracked keyframe integrated" for every frame that went through the
// pipeline, so LOST frames (whose poses in trajectory_camera.txt are only the motion prediction)
// are visible to the user; tracked/keyframe/integrated are 0 or 1.
std::string frames_table(const std::vector<FrameOutcome>& frames);

// write_session = false keeps slam_map.bin / kept_clouds.bin out (a run that was interrupted must
// not overwrite the session it loaded from the same folder). The map and session files of an
// earlier run in out_dir that this run does not make are removed (kept when write_session is false).
OutputPaths write_outputs(const Pipeline& pipeline, const PipelineConfig& config, const std::string& out_dir,
                          bool write_session = true);

}  // namespace s3m::pipeline
