#pragma once
// OUT/session.mcap: what a run wrote into OUT as ROS 2 messages that Foxglove and `ros2 bag play`
// open. Frames: "map" (the run's world), "camera" (the colour camera), "base_link" (the robot).
//  - /tf: per frame of trajectory_camera.txt, map -> camera and (with trajectory_robot.txt)
//    map -> base_link, stamped with the frame's recording time;
//  - /s3m/camera_path, /s3m/robot_path: nav_msgs/msg/Path of those poses, at the last frame's time;
//  - /s3m/map/cloud: sensor_msgs/msg/PointCloud2 of the semantic map's occupied voxels (map.ot):
//    x, y, z (float32, voxel centre [m]), rgb (float32-packed 0x00RRGGBB, observed colour),
//    class_id (uint16), confidence (float32, probability of class_id);
//  - /s3m/map/markers: visualization_msgs/msg/MarkerArray, one CUBE_LIST per class in its palette
//    colour (text: the class name);
//  - /s3m/map/objects: MarkerArray, the object instances (mapping::object_instances, 10 voxels or
//    more) as boxes (namespace: the class name) and labels "chair 2 (0.120 m3)";
//  - /s3m/keyframe/segmentation (sensor_msgs/msg/CompressedImage, png in the class palette colours)
//    and /s3m/keyframe/labels (CompressedImage, "16UC1; png": the class ids) per keyframe at its
//    time; /s3m/camera_info once.
#include <cstdint>
#include <string>
#include <vector>

#include <opencv2/core.hpp>

#include "s3m/core/camera.hpp"

namespace s3m::rosbag2 {

// A keyframe's segmentation, kept while the run goes.
struct KeyframeLabels {
  double t_s = 0;                     // the keyframe's recording time [s]
  std::vector<std::uint8_t> ids_png;  // 16-bit PNG of the class id per pixel (the segmenter's top label)
};
// The PNG a KeyframeLabels holds (kept compressed: a long run has hundreds of keyframes).
std::vector<std::uint8_t> keyframe_png(const cv::Mat& class_ids);

// camera: the colour camera, written once as /s3m/camera_info (frame "camera") at the first
// frame's time; nullptr: none. keyframes: in time order. Returns the path written
// (OUT/session.mcap), or "" when the run has no camera pose (no tracked frame: nothing written, an
// earlier session.mcap removed). Throws s3m::Error naming the file it cannot read or write; an
// earlier session.mcap stays until the new one is complete.
std::string write_session_mcap(const std::string& out_dir, const PinholeCamera* camera = nullptr,
                               const std::vector<KeyframeLabels>& keyframes = {});

}  // namespace s3m::rosbag2
