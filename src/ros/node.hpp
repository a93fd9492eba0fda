#pragma once
// s3m_node: the ROS1 front end of s3m::pipeline. A thin layer: messages in -> RgbdFrame ->
// Pipeline::process() -> messages out. All parameters and topics are listed in README.md ("ROS1").
//
// Frames are processed inline in the subscriber callback with the pipeline in deterministic mode
// (one thread), so the map can be read for publishing between frames without locks. Frames that
// arrive while one is being processed wait in the subscriber queues (~queue_size); older ones drop.
//
// Frames: `map` is the robot body frame at the first tracked frame (x forward, z up for a level
// start, REP 103); the SLAM world (the first keyframe's camera frame) is T_map_w from it. With ~map
// it is the saved run's `map` frame (the robot at its first keyframe), so sessions share one frame.
#include <memory>
#include <optional>
#include <string>

#include <message_filters/subscriber.h>
#include <ros/ros.h>
#include <sensor_msgs/CameraInfo.h>
#include <sensor_msgs/Image.h>
#include <std_msgs/String.h>
#include <std_srvs/Trigger.h>
#include <tf2_ros/buffer.h>
#include <tf2_ros/static_transform_broadcaster.h>
#include <tf2_ros/transform_broadcaster.h>
#include <tf2_ros/transform_listener.h>

#include "s3m/io/depth_to_colour.hpp"
#include "s3m/pipeline/pipeline.hpp"

namespace s3m::ros1 {

struct NodeParams {
  pipeline::PipelineConfig config;
  std::string map_frame = "map", odom_frame = "odom", base_frame = "base_link";
  bool use_odom_tf = false;        // true: odom -> base_link comes from another node; s3m publishes map -> odom
  bool T_c_r_from_tf = false;      // true: T_c_r = TF base_frame <- camera frame; false: config slam.T_c_r
  bool publish_camera_tf = true;   // with T_c_r from config: static base_frame -> camera frame
  bool use_labels = false;         // subscribe labels/image (mono16 class ids) for the oracle segmenter
  bool approximate_sync = false;   // ApproximateTime instead of exact stamps (drivers without registration)
  int queue_size = 10;
  int map_every_n_frames = 10;     // publish map/markers and map/cloud every n processed frames
  double camera_bf = 40.0;         // virtual stereo bf [px m] when CameraInfo's P[3] does not carry it
  bool camera_from_config = false;  // the preset's dataset.camera instead of the driver's CameraInfo
  // Depth not registered to colour (realsense2_camera without align_depth): drawn into the colour
  // camera with depth/camera_info and the TF colour frame <- depth frame (io::DepthToColour).
  bool align_depth = false;
  std::string output_dir;          // ~save_map and save_on_exit write here ("" = nowhere)
  bool save_on_exit = true;
  // A saved run to continue in (a folder `s3m run --out`, ~save_map or save_on_exit wrote:
  // slam_map.bin + kept_clouds.bin): relocalise in it, extend it (or, with localize_only, leave the
  // SLAM map as it is); `map` is then the saved run's map frame. "" = start from nothing. ~map as a
  // string; as a dictionary it stays the preset's `map:` section override (ros_params.hpp).
  std::string map;
  bool localize_only = false;
  bool force = false;              // run even when the map's cost is over the limit (s3m run --force)
};
NodeParams read_node_params(const ros::NodeHandle& pnh);

class S3mNode {
 public:
  S3mNode(ros::NodeHandle nh, ros::NodeHandle pnh);
  ~S3mNode();
  // Finishes the pipeline (final map rebuild) and, with save_on_exit, writes the outputs.
  void shutdown();
  bool failed() const { return failed_; }  // a frame error stopped the node

 private:
  using ImageCPtr = sensor_msgs::ImageConstPtr;
  void on_frame(const ImageCPtr& rgb, const ImageCPtr& depth, const sensor_msgs::CameraInfoConstPtr& info,
                const ImageCPtr& labels);
  // Builds the pipeline on the first frame (its camera info; `first` decides the depth registration;
  // depth_frame: the depth image's frame_id, for ~align_depth).
  void start(const sensor_msgs::CameraInfo& info, const std::string& camera_frame, const std::string& depth_frame,
             const RgbdFrame& first);
  void on_depth_info(const sensor_msgs::CameraInfoConstPtr& info) { depth_info_ = info; }
  // ~align_depth: the depth camera and its pose from depth/camera_info and TF; returns who registered it.
  std::string start_alignment(const std::string& colour_frame, const std::string& depth_frame,
                              const PinholeCamera& colour);
  void on_outcome(const pipeline::FrameOutcome& o, const semantics::LabelMap& labels);
  void publish_poses(const SE3& T_w_c, const ros::Time& stamp);
  void publish_map(const ros::Time& stamp);
  bool save_map(std_srvs::Trigger::Request&, std_srvs::Trigger::Response& res);
  void on_query(const std_msgs::String& cls);
  void save(const std::string& dir);

  ros::NodeHandle nh_, pnh_;
  NodeParams params_;
  message_filters::Subscriber<sensor_msgs::Image> rgb_sub_, depth_sub_, labels_sub_;
  message_filters::Subscriber<sensor_msgs::CameraInfo> info_sub_;
  std::shared_ptr<void> sync_;  // the message_filters synchronizer (its type depends on the params)
  ros::Publisher cam_odom_, cam_pose_, robot_odom_, robot_pose_, markers_, cloud_, seg_, labels_;
  ros::Publisher query_result_, query_markers_;
  ros::Subscriber query_sub_, depth_info_sub_;
  sensor_msgs::CameraInfoConstPtr depth_info_;               // ~align_depth: the latest depth/camera_info
  std::shared_ptr<const io::DepthToColour> to_colour_;       // ~align_depth, from the first frame on
  ros::ServiceServer save_srv_;
  tf2_ros::Buffer tf_buffer_;
  tf2_ros::TransformListener tf_listener_{tf_buffer_};
  tf2_ros::TransformBroadcaster tf_;
  tf2_ros::StaticTransformBroadcaster static_tf_;

  std::unique_ptr<pipeline::Pipeline> pipeline_;
  std::string camera_frame_;
  std::optional<SE3> T_map_w_;  // set at the first tracked frame
  ros::Time stamp_;             // of the frame being processed
  int frames_ = 0;
  bool finished_ = false;
  bool failed_ = false;
};

}  // namespace s3m::ros1
