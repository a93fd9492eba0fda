#pragma once
// Which camera driver or recorder wrote a bag, from its topic names and types alone, so that
// `s3m run --rosbag FILE.bag` reads a recording as it comes off the camera without topic options:
//  - TUM RGB-D benchmark bags: /camera/rgb/image_color, /camera/depth/image (registered);
//  - the RealSense SDK (realsense-viewer, rs-record): /device_0/sensor_N/Color_0/image/data next to
//    /device_0/sensor_M/Depth_0/image/data, raw streams with their own CameraInfo, extrinsics on
//    <stream>/tf/<reference> and the depth unit on /device_0/sensor_M/option/Depth Units/value;
//  - realsense2_camera (ROS): NS/color/image_raw with NS/aligned_depth_to_color/image_raw
//    (registered) or else NS/depth/image_rect_raw (raw; extrinsics from /tf_static);
//  - openni_launch / openni2_launch (Kinect v1, Xtion, Astra): NS/rgb/image_color, image_raw (a
//    Kinect's is Bayer) or image_rect_color (rectified: its CameraInfo's D no longer applies) with
//    NS/depth_registered/image_raw or NS/depth_registered/image (registered);
//  - the Azure Kinect ROS driver: NS/rgb/image_raw with NS/depth_to_rgb/image_raw (registered).
// No ROS header here: the recogniser works on a topic -> message type table.
#include <map>
#include <optional>
#include <string>

namespace s3m::ros1 {

struct BagRecording {
  std::string recorder;  // who wrote the bag, for the log: "RealSense SDK (realsense-viewer, rs-record)", ...
  std::string rgb, depth;
  std::string rgb_info;  // sensor_msgs/CameraInfo of the colour stream ("" = none in the bag)
  // Raw depth (not registered to colour): the depth stream's CameraInfo; "" = registered.
  std::string depth_info;
  // How the depth camera sits relative to the colour camera when depth_info is set: the RealSense
  // SDK's geometry_msgs/Transform topics (reference stream -> stream), or both "" for /tf_static.
  std::string rgb_extrinsics, depth_extrinsics;
  std::string depth_units;  // std_msgs/Float32 metres per unit of 16-bit depth ("" = millimetres)
  // The driver that registered the depth topic to colour ("" = not known: TUM bags, topics given).
  std::string registered_by;
  // The colour CameraInfo is the device's factory calibration (RealSense, Azure Kinect), better
  // than a preset's camera file; openni's and the TUM bags' hold the driver's defaults.
  bool device_calibration = false;
  bool registered() const { return depth_info.empty(); }
};

// topic -> message type (e.g. "sensor_msgs/Image") of every connection in the bag. Throws
// s3m::Error when no recorder above matches (listing the bag's image topics and what s3m looks
// for) or when several cameras do (naming them; --rgb-topic/--depth-topic choose one).
BagRecording recognise_recording(const std::map<std::string, std::string>& topic_types);

// The recording whose colour and depth topics are `rgb` and `depth` (topics given on the command
// line, e.g. one camera of a rig that recorded two): what its recorder wrote beside them (a raw
// depth stream's CameraInfo and extrinsics, the depth unit, who registered it). nullopt when no
// recorder above wrote that pair. Only that camera's topics are looked at (those under the
// namespace both share); throws s3m::Error as recognise_recording does when they are incomplete
// (not for topics that share no namespace: nullopt).
std::optional<BagRecording> recording_with(const std::map<std::string, std::string>& topic_types,
                                           const std::string& rgb, const std::string& depth);

}  // namespace s3m::ros1
