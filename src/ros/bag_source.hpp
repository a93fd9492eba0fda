#pragma once
// A rosbag as a pipeline::FrameSource, read with the rosbag C++ API (`s3m run --rosbag`).
// Colour and depth images are paired by header stamp: each colour image takes the depth image with
// the nearest stamp within dataset.max_dt_s (each depth image used once; unpaired colour images are
// skipped and counted). The camera comes from the first CameraInfo on camera_info_topic, or from
// dataset.camera (a preset or camera YAML) when that is set or no CameraInfo topic is given.
#include <memory>
#include <string>

#include "s3m/pipeline/frame_source.hpp"

namespace s3m::ros1 {

struct BagTopics {
  std::string rgb = "/camera/rgb/image_color";
  std::string depth = "/camera/depth/image";
  std::string camera_info = "/camera/rgb/camera_info";  // "" = camera from dataset.camera
  std::string labels;                                   // optional mono16 class ids (s3m simulator)
  std::string groundtruth = "/groundtruth";             // optional geometry_msgs/PoseStamped T_w_c
};

// Throws s3m::Error naming the bag and topic (missing file, topic absent, wrong message type).
std::unique_ptr<pipeline::FrameSource> open_bag_source(const std::string& bag_path, const BagTopics& topics,
                                                       const pipeline::DatasetConfig& dataset);

}  // namespace s3m::ros1
