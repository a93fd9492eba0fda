#pragma once
// Writes a TUM-layout directory (real, or from `s3m sim`) into a ROS1 bag (`s3m tum2bag`), for
// testing the node and `s3m run --rosbag`. Per frame, all stamped with the colour image's time
// (header stamp = bag time): colour (rgb8), depth (32FC1 metres, bit-exact with what TumDataset
// loads, or 16UC1 millimetres as a driver sends it), CameraInfo, and the label image (mono16) when
// the sequence has labels; every ground-truth pose as geometry_msgs/PoseStamped on `groundtruth`.
#include <cstddef>
#include <string>

#include "bag_source.hpp"

namespace s3m::ros1 {

struct BagWriteOptions {
  BagTopics topics;                           // labels "" = do not write label images
  std::string depth_encoding = "32FC1";       // 32FC1 | 16UC1
  std::string camera_frame = "camera_rgb_optical_frame";
  std::string world_frame = "world";          // frame of the ground-truth poses
  long max_frames = -1;                       // < 0: all
};

// Returns the number of frames written. Throws s3m::Error / ParseError for a bad dataset.
std::size_t write_tum_to_bag(const std::string& dataset_dir, const std::string& bag_path,
                             const BagWriteOptions& options);

}  // namespace s3m::ros1
