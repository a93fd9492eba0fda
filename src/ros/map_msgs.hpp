#pragma once
// The semantic map and the labels as ROS messages. Octomap_msgs is not packaged in Debian 12, so
// the map goes out as a MarkerArray of class-coloured voxel cubes (one CUBE_LIST per class, namespace
// = class name) and as a PointCloud2 of occupied voxel centres with fields x y z rgb label confidence.
// Voxels are in the map's (SLAM world) frame; T_frame_w moves them into the published frame.
#include <string>

#include <ros/time.h>
#include <sensor_msgs/Image.h>
#include <sensor_msgs/PointCloud2.h>
#include <visualization_msgs/MarkerArray.h>

#include "s3m/core/se3.hpp"
#include "s3m/mapping/semantic_octree.hpp"
#include "s3m/semantics/label_map.hpp"

namespace s3m::ros1 {

struct Stamp {
  ros::Time time;
  std::string frame_id;
};

// First marker: DELETEALL (classes that vanished disappear in RViz), then one CUBE_LIST per class
// with voxels; unlabelled occupied voxels are grey in namespace "unknown".
visualization_msgs::MarkerArray map_markers(const mapping::SemanticOcTree& tree, const SE3& T_frame_w, const Stamp& s);

// x y z (float32, metres, in s.frame_id), rgb (float32-packed, observed colour), label (uint16
// class id), confidence (float32 probability of label).
sensor_msgs::PointCloud2 map_cloud(const mapping::SemanticOcTree& tree, const SE3& T_frame_w, const Stamp& s);

// Class-palette colour image (rgb8) and the class-id image (mono16) of a frame's top labels.
sensor_msgs::Image segmentation_image(const semantics::LabelMap& labels, const ClassList& classes, const Stamp& s);
sensor_msgs::Image label_image(const semantics::LabelMap& labels, const Stamp& s);

}  // namespace s3m::ros1
