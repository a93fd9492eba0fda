// ROS 2 recordings for `s3m run REC` and `s3m check REC`: read in every build (s3m::rosbag2).
#include <spdlog/spdlog.h>

#include "ros_support.hpp"
#include "s3m/rosbag2/recording.hpp"
#include "s3m/rosbag2/source.hpp"

namespace s3m::apps {

std::function<std::unique_ptr<pipeline::FrameSource>(const pipeline::PipelineConfig&)> ros2_source(
    const std::string& recording, const RosbagArgs& a, pipeline::PipelineConfig& config, bool config_given,
    PinholeCamera* camera) {
  rosbag2::Rosbag2Topics t{a.rgb_topic, a.depth_topic, a.camera_info_topic, a.labels_topic, a.gt_topic};
  t.validate();
  auto opened = std::make_shared<std::unique_ptr<rosbag2::Rosbag2Source>>(
      rosbag2::open_rosbag2_source(recording, t, config.dataset));
  if (camera) *camera = (*opened)->camera();
  if (const auto T_c_r = (*opened)->T_c_r(); T_c_r && !config_given) {
    config.slam.T_c_r = *T_c_r;
    spdlog::info("{}: no --config: T_c_r (robot -> camera) from /tf_static ({} -> the camera's frame)",
                 recording, (*opened)->robot_frame());
  }
  // The run asks once; a second request (not made today) opens the recording again.
  return [recording, t, opened](const pipeline::PipelineConfig& c) -> std::unique_ptr<pipeline::FrameSource> {
    if (*opened) return std::move(*opened);
    return rosbag2::open_rosbag2_source(recording, t, c.dataset);
  };
}

bool is_ros2_recording(const std::string& path) { return rosbag2::is_recording(path); }

}  // namespace s3m::apps
