#pragma once
// What one scan of a recording finds, kept small: every topic with its type and message count,
// every image message's header stamp and place (not its pixels), the first CameraInfo of each
// topic, the /tf_static tree and the pose topics' poses. A frame source reads images again by
// their MessageRef when a frame is loaded.
#include <cstdint>
#include <map>
#include <string>
#include <vector>

#include "s3m/rosbag2/cdr.hpp"
#include "s3m/rosbag2/recording.hpp"
#include "s3m/rosbag2/static_tf.hpp"
#include "s3m/rosbag2/topics.hpp"

namespace s3m::rosbag2 {

struct StampedRef {
  double t_s = 0;  // header stamp [s]
  MessageRef ref;
};

struct TopicStats {
  std::string type, encoding;
  std::size_t messages = 0;
  std::int64_t first_ns = 0, last_ns = 0;  // log times
  std::uint64_t bytes = 0;
  // Messages per second over the recording of this topic (0 with fewer than two messages).
  double rate_hz() const;
};

struct RecordingIndex {
  std::map<std::string, TopicStats> topics;
  std::map<std::string, std::vector<StampedRef>> images;  // Image and CompressedImage topics, by stamp
  std::map<std::string, CameraInfo> first_info;           // CameraInfo topics
  std::map<std::string, SE3> first_extrinsics;            // realsense2_camera's Extrinsics topics
  StaticTf tf_static;
  std::map<std::string, std::vector<PoseStamped>> poses;  // PoseStamped and Odometry topics, by stamp
  TopicTypes types() const;
};

// One pass over every message. Throws s3m::Error naming the file and message (Recording::locate)
// when a message of a type read here does not decode, or is not CDR.
RecordingIndex index_recording(Recording& rec);

}  // namespace s3m::rosbag2
