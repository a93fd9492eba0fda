#include "s3m/rosbag2/recording_index.hpp"

#include <algorithm>

namespace s3m::rosbag2 {

double TopicStats::rate_hz() const {
  return messages > 1 && last_ns > first_ns ? (messages - 1) * 1e9 / static_cast<double>(last_ns - first_ns)
                                            : 0.0;
}

TopicTypes RecordingIndex::types() const {
  TopicTypes t;
  for (const auto& [topic, s] : topics) t[topic] = s.type;
  return t;
}

namespace {

void count(TopicStats& s, const MessageView& m) {
  if (s.messages == 0 || m.log_time_ns < s.first_ns) s.first_ns = m.log_time_ns;
  if (s.messages == 0 || m.log_time_ns > s.last_ns) s.last_ns = m.log_time_ns;
  ++s.messages;
  s.bytes += m.data.size;
}

void add(RecordingIndex& x, const MessageView& m, const std::string& where) {
  const std::string& type = m.channel->type;
  const std::string& topic = m.channel->topic;
  if (type == "sensor_msgs/msg/Image" || type == "sensor_msgs/msg/CompressedImage") {
    CdrReader r(m.data, where);
    x.images[topic].push_back({read_header(r).stamp_s(), m.ref});
  } else if (type == "sensor_msgs/msg/CameraInfo") {
    if (!x.first_info.count(topic)) x.first_info[topic] = decode_camera_info(m.data, where);
  } else if (type == "realsense2_camera_msgs/msg/Extrinsics") {
    if (!x.first_extrinsics.count(topic)) x.first_extrinsics[topic] = decode_extrinsics(m.data, where);
  } else if (type == "tf2_msgs/msg/TFMessage" && topic == "/tf_static") {
    for (const TransformStamped& t : decode_tf_message(m.data, where)) x.tf_static.add(t);
  } else if (type == "geometry_msgs/msg/PoseStamped") {
    x.poses[topic].push_back(decode_pose_stamped(m.data, where));
  } else if (type == "nav_msgs/msg/Odometry") {
    x.poses[topic].push_back(decode_odometry(m.data, where));
  }
}

bool decoded_here(const std::string& type) {
  return type == "sensor_msgs/msg/Image" || type == "sensor_msgs/msg/CompressedImage" ||
         type == "sensor_msgs/msg/CameraInfo" || type == "tf2_msgs/msg/TFMessage" ||
         type == "geometry_msgs/msg/PoseStamped" || type == "nav_msgs/msg/Odometry" ||
         type == "realsense2_camera_msgs/msg/Extrinsics";
}

}  // namespace

RecordingIndex index_recording(Recording& rec) {
  RecordingIndex x;
  rec.scan([&](const MessageView& m) {
    TopicStats& s = x.topics[m.channel->topic];
    s.type = m.channel->type, s.encoding = m.channel->encoding;
    count(s, m);
    if (!decoded_here(s.type)) return;
    const std::string where = rec.locate(m.ref) + " (" + m.channel->topic + ", " + s.type + ")";
    if (s.encoding != "cdr") throw Error(where + ": message encoding '" + s.encoding + "' (expected cdr)");
    add(x, m, where);
  });
  for (auto& [topic, v] : x.images)
    std::stable_sort(v.begin(), v.end(),
                     [](const StampedRef& a, const StampedRef& b) { return a.t_s < b.t_s; });
  for (auto& [topic, v] : x.poses)
    std::stable_sort(v.begin(), v.end(), [](const PoseStamped& a, const PoseStamped& b) {
      return a.header.stamp_s() < b.header.stamp_s();
    });
  return x;
}

}  // namespace s3m::rosbag2
