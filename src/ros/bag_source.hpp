#pragma once
// A rosbag as a pipeline::FrameSource, read with the rosbag C++ API (`s3m run --rosbag`).
// Topics: the ones given, or, when neither a colour nor a depth topic is given, the recorder's
// (bag_recordings.hpp: TUM RGB-D, the RealSense SDK, realsense2_camera, openni, Azure Kinect). A
// raw depth stream (not registered to colour) is drawn into the colour camera (io::DepthToColour)
// with the depth camera's CameraInfo and the recorded extrinsics (RealSense SDK) or /tf_static.
// Colour and depth images are paired by header stamp: each colour image takes the depth image with
// the nearest stamp within dataset.max_dt_s (each depth image used once; unpaired colour images are
// skipped and counted). The camera comes from the first CameraInfo on camera_info_topic, or from
// dataset.camera (a preset or camera YAML) when that is set or no CameraInfo topic is given.
#include <memory>
#include <string>

#include "s3m/pipeline/frame_source.hpp"

namespace s3m::ros1 {

// The defaults are the TUM RGB-D bags' names (what `s3m tum2bag` writes). For reading, rgb and
// depth both "" = recognise the recorder; camera_info "" = the recognised (or the colour topic's
// sibling) camera_info topic or dataset.camera (precedence in bag_source.cpp, read_camera), "none"
// = dataset.camera.
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
