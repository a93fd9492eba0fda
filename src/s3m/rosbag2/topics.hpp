#pragma once
// Which camera driver wrote a ROS 2 recording, from its topic names and types alone, so that
// `s3m run REC` reads a recording as it comes off the camera without topic options. NS is the
// driver's namespace (realsense2_camera's default is /camera/camera); colour and depth may also be
// image_transport's compressed topics (IMAGE/compressed, DEPTH/compressedDepth):
//  - realsense2_camera: NS/color/image_raw with NS/aligned_depth_to_color/image_raw (registered)
//    or else NS/depth/image_rect_raw (raw: its NS/depth/camera_info and /tf_static, or else
//    NS/extrinsics/depth_to_color, place it);
//  - azure_kinect_ros_driver: NS/rgb/image_raw with NS/depth_to_rgb/image_raw (registered);
//  - orbbec_camera: NS/color/image_raw with NS/depth/image_raw (registered when the driver's
//    depth_registration made its CameraInfo the colour camera's, else raw);
//  - the TUM RGB-D names `s3m tum2bag` and the simulator's recordings use: /camera/rgb/image_color
//    with /camera/depth/image (registered), labels on /camera/labels.
#include <map>
#include <string>
#include <vector>

namespace s3m::rosbag2 {

struct TopicSet {
  std::string recorder;  // for the log: "realsense2_camera", "topics given", ...
  std::string rgb, depth;
  std::string rgb_info;    // sensor_msgs/msg/CameraInfo of colour ("" = none in the recording)
  std::string depth_info;  // raw depth: the depth camera's CameraInfo; "" = registered to colour
  std::string labels;      // optional class-id images
  // The depth is registered exactly when the depth CameraInfo is the colour camera's (orbbec).
  bool registered_if_same_info = false;
  // realsense2_camera's realsense2_camera_msgs/msg/Extrinsics from depth to colour ("" = none): used
  // when /tf_static does not connect the two cameras' frames.
  std::string extrinsics;
  std::string registered_by;        // the driver that registered depth ("" = not known)
  bool device_calibration = false;  // the colour CameraInfo is the device's factory calibration
  bool registered() const { return depth_info.empty(); }
};

// topic -> ROS 2 type ("sensor_msgs/msg/Image") of every topic of the recording.
using TopicTypes = std::map<std::string, std::string>;

// Every camera a known driver recorded. Empty when none.
std::vector<TopicSet> recognise_cameras(const TopicTypes& types);

// rgb and depth both "" : the one recognised camera (throws s3m::Error when there is none, listing
// the image topics and what s3m looks for, or several, naming them: --rgb-topic/--depth-topic pick
// one). Otherwise those topics, with what their driver recorded beside them when a known driver
// wrote that pair, or else the colour topic's sibling camera_info. camera_info: a topic given on the
// command line ("none" and "" leave the recognised one).
TopicSet choose_topics(const TopicTypes& types, const std::string& rgb, const std::string& depth,
                       const std::string& camera_info);

// The image topics of a recording with their types, for errors: "/a (sensor_msgs/msg/Image), ...".
std::string image_topics(const TopicTypes& types);

}  // namespace s3m::rosbag2
