#pragma once
// The CLI's ROS1 pieces: `s3m run --rosbag` options and `s3m tum2bag`. In a build without ROS the
// options still exist (so --help is the same) and using them says the binary was built without ROS.
#include <string>

#include <CLI/CLI.hpp>

#include "s3m/pipeline/run.hpp"

namespace s3m::apps {

struct RosbagArgs {
  std::string bag;
  std::string rgb_topic = "/camera/rgb/image_color";
  std::string depth_topic = "/camera/depth/image";
  std::string camera_info_topic = "/camera/rgb/camera_info";
  std::string labels_topic;  // optional
  std::string gt_topic = "/groundtruth";
};

void add_rosbag_options(CLI::App& cmd, RosbagArgs& args);
// Throws s3m::Error in a build without ROS.
std::function<std::unique_ptr<pipeline::FrameSource>(const pipeline::PipelineConfig&)> rosbag_source(
    const RosbagArgs& args);

}  // namespace s3m::apps
