#pragma once
// The CLI's ROS pieces: `s3m run --rosbag` options, ROS 2 recordings and `s3m tum2bag`. In a build without
// ROS the options still exist (so --help is the same) and using them says the binary was built without ROS.
#include <string>

#include <CLI/CLI.hpp>

#include "s3m/run/run.hpp"

namespace s3m::apps {

struct RosbagArgs {
  std::string bag;
  // "" = the bag's recorder decides (`s3m run`); `s3m tum2bag` writes the TUM RGB-D names.
  std::string rgb_topic;
  std::string depth_topic;
  std::string camera_info_topic;
  std::string labels_topic;  // optional
  std::string gt_topic = "/groundtruth";
};

void add_rosbag_options(CLI::App& cmd, RosbagArgs& args);
// Throws s3m::Error in a build without ROS.
std::function<std::unique_ptr<pipeline::FrameSource>(const pipeline::PipelineConfig&)> rosbag_source(
    const RosbagArgs& args);

// A ROS 2 recording (a .mcap or .db3 file, or a rosbag2 folder; rosbag2::is_recording) with the
// topic options of `args` (its bag is not used); every build reads them (ros2_support.cpp). Opened
// here, with config's dataset section, so that without a preset (config_given false) the
// recording's /tf_static sets slam.T_c_r, as a simulator folder's sim.yaml does. camera: when set,
// receives the recording's colour camera.
std::function<std::unique_ptr<pipeline::FrameSource>(const pipeline::PipelineConfig&)> ros2_source(
    const std::string& recording, const RosbagArgs& args, pipeline::PipelineConfig& config, bool config_given,
    PinholeCamera* camera = nullptr);
bool is_ros2_recording(const std::string& path);

}  // namespace s3m::apps
