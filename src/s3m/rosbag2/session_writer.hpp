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
//    more) as boxes (namespace: the class name) and labels "chair 2 (0.120 m3)".
#include <string>

#include "s3m/core/camera.hpp"

namespace s3m::rosbag2 {

// camera: the colour camera, written once as /s3m/camera_info (frame "camera") at the first frame's
// time; nullptr: none. Returns the path written (OUT/session.mcap). Throws s3m::Error naming the
// file it cannot read or write; an earlier session.mcap stays until the new one is complete.
std::string write_session_mcap(const std::string& out_dir, const PinholeCamera* camera = nullptr);

}  // namespace s3m::rosbag2
