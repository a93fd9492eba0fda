#include "s3m/rosbag2/topics.hpp"

#include <algorithm>

#include "s3m/core/error.hpp"

namespace s3m::rosbag2 {
namespace {

const std::string kImage = "sensor_msgs/msg/Image", kCompressed = "sensor_msgs/msg/CompressedImage",
                  kInfo = "sensor_msgs/msg/CameraInfo", kExtrinsics = "realsense2_camera_msgs/msg/Extrinsics";

struct Driver {
  const char* name;
  const char* colour;                   // relative to NS
  const char* colour_info;              // relative to NS
  std::vector<const char*> registered;  // depth topics registered to colour, in order of preference
  const char* raw = "";                 // raw depth, when no registered one
  const char* raw_info = "";
  bool same_info_registers = false;
  bool device_calibration = true;
};

const std::vector<Driver>& drivers() {
  static const std::vector<Driver> d = {
      {"realsense2_camera",
       "color/image_raw",
       "color/camera_info",
       {"aligned_depth_to_color/image_raw"},
       "depth/image_rect_raw",
       "depth/camera_info"},
      {"azure_kinect_ros_driver", "rgb/image_raw", "rgb/camera_info", {"depth_to_rgb/image_raw"}},
      {"orbbec_camera",
       "color/image_raw",
       "color/camera_info",
       {},
       "depth/image_raw",
       "depth/camera_info",
       true},
      {"TUM RGB-D names (s3m tum2bag, the simulator)",
       "rgb/image_color",
       "rgb/camera_info",
       {"depth/image"},
       "",
       "",
       false,
       false},
  };
  return d;
}

bool has(const TopicTypes& t, const std::string& topic, const std::string& type) {
  const auto it = t.find(topic);
  return it != t.end() && it->second == type;
}

// The image topic at `base`, raw or as image_transport's compressed topic; "" when neither.
std::string image_at(const TopicTypes& t, const std::string& base, bool depth) {
  if (has(t, base, kImage)) return base;
  const std::string c = base + (depth ? "/compressedDepth" : "/compressed");
  return has(t, c, kCompressed) ? c : "";
}

bool ends_with(const std::string& s, const std::string& tail) {
  return s.size() >= tail.size() && s.compare(s.size() - tail.size(), tail.size(), tail) == 0;
}

std::string info_at(const TopicTypes& t, const std::string& topic) {
  return has(t, topic, kInfo) ? topic : "";
}

}  // namespace

std::vector<TopicSet> recognise_cameras(const TopicTypes& types) {
  std::vector<TopicSet> out;
  for (const Driver& d : drivers())
    for (const auto& [topic, type] : types) {
      if (type != kImage || !ends_with(topic, d.colour)) continue;
      const std::string ns = topic.substr(0, topic.size() - std::string(d.colour).size());
      TopicSet s;
      s.recorder = d.name;
      s.rgb = image_at(types, topic, false);
      for (const char* r : d.registered)
        if (s.depth.empty()) s.depth = image_at(types, ns + r, true);
      if (!s.depth.empty()) {
        s.registered_by = d.device_calibration ? d.name : "";
      } else if (*d.raw) {
        s.depth = image_at(types, ns + d.raw, true);
        s.depth_info = info_at(types, ns + d.raw_info);
        s.registered_if_same_info = d.same_info_registers;
        if (s.depth_info.empty()) continue;  // raw depth without its camera: not this driver's set
        if (has(types, ns + "extrinsics/depth_to_color", kExtrinsics))
          s.extrinsics = ns + "extrinsics/depth_to_color";
      }
      if (s.depth.empty()) continue;
      s.rgb_info = info_at(types, ns + d.colour_info);
      s.device_calibration = d.device_calibration;
      if (!d.device_calibration) s.labels = has(types, ns + "labels", kImage) ? ns + "labels" : "";
      out.push_back(s);
    }
  // Compressed copies of a colour topic are found through its raw topic above; a recording holding
  // only compressed colour is matched here.
  for (const Driver& d : drivers())
    for (const auto& [topic, type] : types) {
      const std::string tail = std::string(d.colour) + "/compressed";
      if (type != kCompressed || !ends_with(topic, tail) ||
          has(types, topic.substr(0, topic.size() - 11), kImage))
        continue;
      TopicTypes raw = types;
      raw[topic.substr(0, topic.size() - 11)] = kImage;
      for (TopicSet s : recognise_cameras(raw)) {
        const bool seen =
            std::any_of(out.begin(), out.end(), [&](const TopicSet& o) { return o.rgb == topic; });
        if (s.rgb == topic.substr(0, topic.size() - 11) && !seen) s.rgb = topic, out.push_back(s);
      }
    }
  return out;
}

std::string image_topics(const TopicTypes& types) {
  std::string list;
  for (const auto& [topic, type] : types)
    if (type == kImage || type == kCompressed) list += (list.empty() ? "" : ", ") + topic + " (" + type + ")";
  return list.empty() ? "none" : list;
}

TopicSet choose_topics(const TopicTypes& types, const std::string& rgb, const std::string& depth,
                       const std::string& camera_info) {
  const std::vector<TopicSet> known = recognise_cameras(types);
  TopicSet s;
  if (rgb.empty() && depth.empty()) {
    if (known.empty())
      throw Error("no camera driver's topics recognised among the image topics: " + image_topics(types) +
                  " (expected realsense2_camera, azure_kinect_ros_driver, orbbec_camera or TUM RGB-D names; "
                  "--rgb-topic and --depth-topic name the topics)");
    if (known.size() > 1) {
      std::string list;
      for (const TopicSet& k : known)
        list += (list.empty() ? "" : "; ") + k.recorder + ": " + k.rgb + " + " + k.depth;
      throw Error("several cameras recorded (" + list + "): --rgb-topic and --depth-topic choose one");
    }
    s = known.front();
  } else {
    s.recorder = "topics given";
    for (const TopicSet& k : known)
      if ((rgb.empty() || k.rgb == rgb) && (depth.empty() || k.depth == depth))
        s = k, s.recorder += ", topics given";
    if (!rgb.empty()) s.rgb = rgb;
    if (!depth.empty()) s.depth = depth;
    if (s.rgb.empty() || s.depth.empty())
      throw Error(
          "give both --rgb-topic and --depth-topic, or neither (image topics: " + image_topics(types) + ")");
    if (s.rgb_info.empty()) {  // the colour topic's sibling, as drivers name them
      std::string base = s.rgb;
      if (ends_with(base, "/compressed")) base.resize(base.size() - 11);
      s.rgb_info = info_at(types, base.substr(0, base.rfind('/') + 1) + "camera_info");
    }
  }
  if (!camera_info.empty() && camera_info != "none") s.rgb_info = camera_info;
  return s;
}

}  // namespace s3m::rosbag2
