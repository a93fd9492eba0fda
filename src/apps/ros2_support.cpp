// ROS 2 recordings for `s3m run REC` and `s3m check REC`: read in every build (s3m::rosbag2).
#include "ros_support.hpp"
#include "s3m/rosbag2/recording.hpp"
#include "s3m/rosbag2/source.hpp"

namespace s3m::apps {

std::function<std::unique_ptr<pipeline::FrameSource>(const pipeline::PipelineConfig&)> ros2_source(
    const std::string& recording, const RosbagArgs& a) {
  rosbag2::Rosbag2Topics t{a.rgb_topic, a.depth_topic, a.camera_info_topic, a.labels_topic, a.gt_topic};
  t.validate();
  return [recording, t](const pipeline::PipelineConfig& c) {
    return rosbag2::open_rosbag2_source(recording, t, c.dataset);
  };
}

bool is_ros2_recording(const std::string& path) { return rosbag2::is_recording(path); }

}  // namespace s3m::apps
