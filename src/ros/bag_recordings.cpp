#include "bag_recordings.hpp"

#include <regex>
#include <set>
#include <vector>

#include "s3m/core/error.hpp"

namespace s3m::ros1 {
namespace {

using Topics = std::map<std::string, std::string>;
const char* const kImage = "sensor_msgs/Image";
const char* const kInfo = "sensor_msgs/CameraInfo";

bool has(const Topics& t, const std::string& topic, const char* type) {
  const auto it = t.find(topic);
  return it != t.end() && it->second == type;
}

std::string if_has(const Topics& t, const std::string& topic, const char* type) {
  return has(t, topic, type) ? topic : "";
}

// Namespaces NS for which NS + suffix is an image topic.
std::vector<std::string> namespaces_with(const Topics& t, const std::string& suffix) {
  std::vector<std::string> out;
  for (const auto& [topic, type] : t)
    if (type == kImage && topic.size() >= suffix.size() &&
        topic.compare(topic.size() - suffix.size(), suffix.size(), suffix) == 0)
      out.push_back(topic.substr(0, topic.size() - suffix.size()));
  return out;
}

// Registered drivers: colour NS + one of rgb_suffixes, depth NS + one of depth_suffixes; one pair
// per namespace, the first suffixes in the lists' order (openni publishes depth_registered/image_raw
// and, through depth_image_proc, depth_registered/image: `rosbag record -a` keeps both).
void add_registered(const Topics& t, const std::string& recorder, const std::vector<std::string>& rgb_suffixes,
                    const std::vector<std::string>& depth_suffixes, const std::string& info_suffix,
                    bool device_calibration, std::vector<BagRecording>& found) {
  std::set<std::string> taken;
  for (const std::string& depth_suffix : depth_suffixes)
    for (const std::string& ns : namespaces_with(t, depth_suffix))
      for (const std::string& rgb_suffix : rgb_suffixes)
        if (!taken.count(ns) && has(t, ns + rgb_suffix, kImage)) {
          taken.insert(ns);
          BagRecording r;
          r.recorder = recorder, r.rgb = ns + rgb_suffix, r.depth = ns + depth_suffix;
          r.rgb_info = if_has(t, ns + info_suffix, kInfo);
          r.registered_by = recorder + " (" + r.depth + ")";
          r.device_calibration = device_calibration;
          found.push_back(r);
          break;
        }
}

// realsense2_camera without align_depth: the raw depth stream, placed by /tf_static.
void add_realsense_ros_raw(const Topics& t, std::vector<BagRecording>& found) {
  for (const std::string& ns : namespaces_with(t, "/depth/image_rect_raw")) {
    if (!has(t, ns + "/color/image_raw", kImage) || has(t, ns + "/aligned_depth_to_color/image_raw", kImage)) continue;
    BagRecording r;
    r.recorder = "realsense2_camera (ROS), depth not aligned";
    r.rgb = ns + "/color/image_raw", r.depth = ns + "/depth/image_rect_raw";
    r.rgb_info = if_has(t, ns + "/color/camera_info", kInfo);
    r.depth_info = if_has(t, ns + "/depth/camera_info", kInfo);
    r.device_calibration = true;
    if (r.depth_info.empty())
      throw Error("the bag holds realsense2_camera's raw depth " + r.depth + " without " + ns +
                  "/depth/camera_info, which s3m needs to align it to colour; record it too, or "
                  "align_depth:=true and " + ns + "/aligned_depth_to_color/image_raw");
    found.push_back(r);
  }
}

// The RealSense SDK's own bag layout (librealsense's ros_writer).
void add_realsense_sdk(const Topics& t, std::vector<BagRecording>& found) {
  static const std::regex stream(R"((/device_\d+)/(sensor_\d+)/(Color|Depth)_0/image/data)");
  std::map<std::string, std::map<std::string, std::string>> by_device;  // device -> Color|Depth -> stream prefix
  std::map<std::string, std::string> depth_sensor;                     // device -> its depth sensor prefix
  for (const auto& [topic, type] : t) {
    std::smatch m;
    if (type != kImage || !std::regex_match(topic, m, stream)) continue;
    by_device[m[1]][m[3]] = m[1].str() + "/" + m[2].str() + "/" + m[3].str() + "_0";
    if (m[3] == "Depth") depth_sensor[m[1]] = m[1].str() + "/" + m[2].str();
  }
  for (const auto& [device, streams] : by_device) {
    if (streams.size() != 2) continue;
    const std::string colour = streams.at("Color"), depth = streams.at("Depth");
    BagRecording r;
    r.recorder = "RealSense SDK (realsense-viewer, rs-record)";
    r.rgb = colour + "/image/data", r.depth = depth + "/image/data";
    r.rgb_info = if_has(t, colour + "/info/camera_info", kInfo);
    r.depth_info = depth + "/info/camera_info";
    r.device_calibration = true;
    if (!has(t, r.depth_info, kInfo))
      throw Error("RealSense SDK bag: no " + r.depth_info + " (the depth camera's intrinsics, needed to align depth to colour)");
    for (const auto& [topic, type] : t) {  // <stream>/tf/<reference id>: the same reference for both
      const std::string prefix = depth + "/tf/";
      if (type == "geometry_msgs/Transform" && topic.rfind(prefix, 0) == 0 &&
          has(t, colour + "/tf/" + topic.substr(prefix.size()), "geometry_msgs/Transform")) {
        r.depth_extrinsics = topic, r.rgb_extrinsics = colour + "/tf/" + topic.substr(prefix.size());
        break;
      }
    }
    if (r.depth_extrinsics.empty())
      throw Error("RealSense SDK bag: no extrinsics " + depth + "/tf/N and " + colour +
                  "/tf/N (where the depth camera sits relative to the colour camera)");
    for (const char* name : {"/option/Depth Units/value", "/option/Depth_Units/value"})
      if (has(t, depth_sensor[device] + name, "std_msgs/Float32")) r.depth_units = depth_sensor[device] + name;
    found.push_back(r);
  }
}

std::string image_topics(const Topics& t) {
  std::string list;
  for (const auto& [topic, type] : t)
    if (type == kImage) list += (list.empty() ? "" : ", ") + topic;
  return list.empty() ? "none" : list;
}

}  // namespace

namespace {

// Every colour/depth pair a recognised recorder wrote, one per camera.
std::vector<BagRecording> recordings_in(const Topics& t) {
  std::vector<BagRecording> found;
  if (has(t, "/camera/rgb/image_color", kImage) && has(t, "/camera/depth/image", kImage)) {
    BagRecording r;
    r.recorder = "TUM RGB-D";
    r.rgb = "/camera/rgb/image_color", r.depth = "/camera/depth/image";
    r.rgb_info = if_has(t, "/camera/rgb/camera_info", kInfo);
    found.push_back(r);
  }
  add_realsense_sdk(t, found);
  add_registered(t, "realsense2_camera (ROS), depth aligned to colour", {"/color/image_raw"},
                 {"/aligned_depth_to_color/image_raw"}, "/color/camera_info", true, found);
  add_realsense_ros_raw(t, found);
  add_registered(t, "openni_launch / openni2_launch", {"/rgb/image_color", "/rgb/image_raw", "/rgb/image_rect_color"},
                 {"/depth_registered/image_raw", "/depth_registered/image", "/depth_registered/sw_registered/image_rect_raw",
                  "/depth_registered/hw_registered/image_rect_raw"},
                 "/rgb/camera_info", false, found);
  add_registered(t, "Azure Kinect ROS driver", {"/rgb/image_raw"}, {"/depth_to_rgb/image_raw"}, "/rgb/camera_info", true, found);
  return found;
}

}  // namespace

BagRecording recognise_recording(const Topics& t) {
  const std::vector<BagRecording> found = recordings_in(t);
  if (found.size() == 1) return found.front();
  if (found.empty())
    throw Error("no colour/depth image pair s3m knows (TUM RGB-D, the RealSense SDK, realsense2_camera, "
                "openni_launch, Azure Kinect); the bag's sensor_msgs/Image topics: " + image_topics(t) +
                "; pass --rgb-topic and --depth-topic");
  std::string list;
  for (const BagRecording& r : found) list += (list.empty() ? "" : "; ") + r.recorder + ": " + r.rgb + " + " + r.depth;
  throw Error("the bag holds " + std::to_string(found.size()) + " colour/depth pairs (" + list +
              "); choose one with --rgb-topic and --depth-topic");
}

std::optional<BagRecording> recording_with(const Topics& t, const std::string& rgb, const std::string& depth) {
  // Only the chosen camera's image and CameraInfo topics (those under the namespace its colour and
  // depth topics share) and every other topic (/tf_static, the SDK's options): another camera's
  // incomplete topics are not this run's problem.
  std::size_t common = 0;
  while (common < rgb.size() && common < depth.size() && rgb[common] == depth[common]) ++common;
  const std::string ns = rgb.substr(0, rgb.rfind('/', common) + 1);
  Topics mine;
  for (const auto& [topic, type] : t)
    if (topic.rfind(ns, 0) == 0 || (type != kImage && type != kInfo)) mine[topic] = type;
  std::vector<BagRecording> found;
  try {
    found = recordings_in(mine);
  } catch (const Error&) {
    if (ns == "/") return std::nullopt;  // topics of no one camera: another camera's gaps are not theirs
    throw;
  }
  for (const BagRecording& r : found)
    if (r.rgb == rgb && r.depth == depth) return r;
  return std::nullopt;
}

}  // namespace s3m::ros1
