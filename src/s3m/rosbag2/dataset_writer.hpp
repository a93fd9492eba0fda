#pragma once
// A dataset folder (any layout io::Dataset reads, e.g. a simulator sequence) written as a ROS 2
// recording (`s3m tum2bag --format mcap|db3`), with the names s3m recognises as the simulator's:
// colour rgb8, depth 32FC1 metres (bit for bit the folder's), the colour CameraInfo, labels
// (16UC1) when the folder has them, ground truth T_w_c as PoseStamped, and the robot-to-camera mount
// on /tf_static (base_link -> the camera's frame) when known. Stamps are the folder's times, so a
// run on the recording reads the frames the folder gives.
#include <optional>
#include <string>

#include "s3m/core/se3.hpp"
#include "s3m/io/dataset.hpp"

namespace s3m::rosbag2 {

struct DatasetWriteOptions {
  std::string format = "mcap";       // mcap | db3
  std::string compression = "zstd";  // MCAP chunks: zstd | none
  std::string rgb_topic = "/camera/rgb/image_color";
  std::string depth_topic = "/camera/depth/image";
  std::string camera_info_topic = "/camera/rgb/camera_info";
  std::string labels_topic = "/camera/labels";  // "" = none
  std::string gt_topic = "/groundtruth";        // "" = none
  std::string frame_id = "camera_rgb_optical_frame";
  long max_frames = -1;      // < 0: all
  std::optional<SE3> T_c_r;  // robot -> camera (maps robot points into the camera frame)
  // Throws s3m::Error on an unknown format or compression, or an empty image topic.
  void validate() const;
};

// Returns the number of frames written. Throws s3m::Error naming the file it cannot read or write;
// the recording appears under `path` only when complete.
std::size_t write_dataset(const io::Dataset& dataset, const std::string& path,
                          const DatasetWriteOptions& options);

}  // namespace s3m::rosbag2
