#pragma once
// Conversions between ROS1 messages and s3m types. Only src/ros includes ROS headers.
//  - colour: rgb8 / bgr8 / rgba8 / bgra8 / mono8 / 8-bit Bayer (cv_bridge debayers) -> CV_8UC3 BGR
//    (OpenCV order, as RgbdFrame)
//  - depth: 16UC1 / mono16 (millimetres, the REP 118 convention, unless the recorder says otherwise:
//    the RealSense SDK's Depth Units) or 32FC1 (metres) -> CV_32FC1 metres
//  - labels (s3m simulator): mono16 / 16UC1 class ids -> CV_16UC1
//  - CameraInfo <-> PinholeCamera (K, plumb_bob D, and the virtual stereo term bf in P, see below)
#include <string>

#include <geometry_msgs/Pose.h>
#include <geometry_msgs/Transform.h>
#include <opencv2/core.hpp>
#include <ros/time.h>
#include <sensor_msgs/CameraInfo.h>
#include <sensor_msgs/Image.h>

#include "s3m/core/camera.hpp"
#include "s3m/core/se3.hpp"

namespace s3m::ros1 {

cv::Mat colour_to_bgr(const sensor_msgs::Image& msg);
cv::Mat depth_to_metres(const sensor_msgs::Image& msg, double metres_per_unit = 1e-3);
cv::Mat labels_to_ids(const sensor_msgs::Image& msg);

// RGB-D SLAM's virtual stereo baseline bf = baseline * fx [px m] (ORB-SLAM's Camera.bf) has no
// field in CameraInfo. s3m stores it as a right stereo camera would: P[3] = -bf (Tx = -fx * B).
// P[3] >= 0 (a plain monocular CameraInfo): bf falls back to `default_bf`.
// Distortion: plumb_bob (or rational_polynomial's first five) and the RealSense SDK's "Brown
// Conrady" as they are; its "Inverse Brown Conrady" (the colour streams; coefficients that undo the
// distortion) converted to the equivalent forward coefficients by a least-squares fit.
PinholeCamera camera_from_info(const sensor_msgs::CameraInfo& info, double default_bf);
sensor_msgs::CameraInfo info_from_camera(const PinholeCamera& camera);

// Whether a CameraInfo describes `camera`: the same width and fx within 1 % (what tells a preset's
// camera file from a recording's or a driver's own calibration).
bool info_matches(const sensor_msgs::CameraInfo& info, const PinholeCamera& camera);

// The live node's camera. ROS convention: a driver publishes its camera's calibration (a RealSense
// its factory calibration, any camera what camera_calibration stored), so the CameraInfo wins over
// a preset's dataset.camera (a file for folders of another unit), unless `from_config`
// (~camera_from_config) or the CameraInfo has no focal length (then dataset.camera, if set).
// `note` says which was used and, when both exist and differ, what the other said.
PinholeCamera live_camera(const sensor_msgs::CameraInfo& info, const std::string& config_camera, bool from_config,
                          double default_bf, std::string& note);

// Throws s3m::Error naming the encoding when it is not one of the above.
sensor_msgs::Image bgr_to_msg(const cv::Mat& bgr);            // rgb8
sensor_msgs::Image depth_to_msg(const cv::Mat& depth_m, const std::string& encoding);  // 32FC1 | 16UC1
sensor_msgs::Image labels_to_msg(const cv::Mat& ids);          // mono16

geometry_msgs::Pose to_pose(const SE3& T);
geometry_msgs::Transform to_transform(const SE3& T);
SE3 from_pose(const geometry_msgs::Pose& p);
SE3 from_transform(const geometry_msgs::Transform& t);

// Seconds <-> ros::Time. TUM timestamps have microseconds; ros::Time nanoseconds, so the round trip
// of a "%.6f" stamp gives back the same double after rounding to the microsecond.
ros::Time to_ros_time(double t_s);
double to_seconds(const ros::Time& t);

}  // namespace s3m::ros1
