// What s3m makes of a bag from its topic names alone (bag_recordings.hpp: which recorder, which
// camera, raw or registered depth) and the ROS conversions a recording needs (Bayer colour, the
// RealSense SDK's inverse distortion model, the live node's choice of camera). No bag is written:
// topic tables and messages in memory. The bags themselves: ros_bag_recordings_test.cpp.
#include <map>
#include <string>

#include <cv_bridge/cv_bridge.h>
#include <gtest/gtest.h>
#include <opencv2/calib3d.hpp>
#include <opencv2/imgproc.hpp>

#include "bag_recordings.hpp"
#include "conversions.hpp"
#include "s3m/core/error.hpp"
#include "s3m/io/camera_yaml.hpp"

namespace s3m {
namespace {


namespace fs = std::filesystem;
using Topics = std::map<std::string, std::string>;
const std::string kImage = "sensor_msgs/Image", kInfo = "sensor_msgs/CameraInfo";

std::string error_of(const Topics& t) {
  try {
    ros1::recognise_recording(t);
  } catch (const Error& e) {
    return e.what();
  }
  return "(accepted)";
}

TEST(RosBagRecordings, RealSenseSdkLayoutWithItsUnitsAndExtrinsics) {
  const std::string dev = "/device_0/sensor_", tf = "geometry_msgs/Transform";
  const Topics t{{dev + "1/Color_0/image/data", kImage},          {dev + "0/Depth_0/image/data", kImage},
                 {dev + "1/Color_0/info/camera_info", kInfo},     {dev + "0/Depth_0/info/camera_info", kInfo},
                 {dev + "1/Color_0/tf/0", tf},                    {dev + "0/Depth_0/tf/0", tf},
                 {dev + "0/Infrared_1/image/data", kImage},       {dev + "0/option/Depth Units/value", "std_msgs/Float32"},
                 {"/file_version", "std_msgs/UInt32"}};
  const ros1::BagRecording r = ros1::recognise_recording(t);
  EXPECT_EQ(r.recorder, "RealSense SDK (realsense-viewer, rs-record)");
  EXPECT_EQ(r.rgb, dev + "1/Color_0/image/data");
  EXPECT_EQ(r.depth, dev + "0/Depth_0/image/data");
  EXPECT_EQ(r.rgb_info, dev + "1/Color_0/info/camera_info");
  EXPECT_EQ(r.depth_info, dev + "0/Depth_0/info/camera_info");
  EXPECT_EQ(r.rgb_extrinsics, dev + "1/Color_0/tf/0");
  EXPECT_EQ(r.depth_extrinsics, dev + "0/Depth_0/tf/0");
  EXPECT_EQ(r.depth_units, dev + "0/option/Depth Units/value");
  EXPECT_FALSE(r.registered());
  Topics no_tf = t;
  no_tf.erase(dev + "1/Color_0/tf/0");
  EXPECT_NE(error_of(no_tf).find("no extrinsics /device_0/sensor_0/Depth_0/tf/N"), std::string::npos) << error_of(no_tf);
}

TEST(RosBagRecordings, DriversThatRegisterDepthAndRealsenseRosRaw) {
  const auto recorded = [](const Topics& t) { return ros1::recognise_recording(t); };
  const ros1::BagRecording aligned = recorded({{"/d435/color/image_raw", kImage},
                                               {"/d435/color/camera_info", kInfo},
                                               {"/d435/depth/image_rect_raw", kImage},
                                               {"/d435/aligned_depth_to_color/image_raw", kImage}});
  EXPECT_EQ(aligned.recorder, "realsense2_camera (ROS), depth aligned to colour");
  EXPECT_EQ(aligned.depth, "/d435/aligned_depth_to_color/image_raw");
  EXPECT_EQ(aligned.rgb_info, "/d435/color/camera_info");
  EXPECT_EQ(aligned.registered_by, "realsense2_camera (ROS), depth aligned to colour (/d435/aligned_depth_to_color/image_raw)");
  EXPECT_TRUE(aligned.registered());
  const ros1::BagRecording raw = recorded({{"/camera/color/image_raw", kImage},
                                           {"/camera/color/camera_info", kInfo},
                                           {"/camera/depth/image_rect_raw", kImage},
                                           {"/camera/depth/camera_info", kInfo}});
  EXPECT_EQ(raw.depth_info, "/camera/depth/camera_info");
  EXPECT_TRUE(raw.depth_extrinsics.empty());  // from /tf_static
  // `rosbag record -a` of openni_launch: raw and rectified colour, both registered depth encodings.
  const ros1::BagRecording openni = recorded({{"/camera/rgb/image_raw", kImage},
                                              {"/camera/rgb/image_rect_color", kImage},
                                              {"/camera/rgb/camera_info", kInfo},
                                              {"/camera/depth/image_raw", kImage},
                                              {"/camera/depth_registered/image", kImage},
                                              {"/camera/depth_registered/image_raw", kImage}});
  EXPECT_EQ(openni.recorder, "openni_launch / openni2_launch");
  EXPECT_EQ(openni.depth, "/camera/depth_registered/image_raw");
  EXPECT_EQ(openni.rgb, "/camera/rgb/image_raw");  // not yet rectified: the CameraInfo's D applies
  const ros1::BagRecording k4a = recorded({{"/rgb/image_raw", kImage}, {"/depth_to_rgb/image_raw", kImage},
                                           {"/depth/image_raw", kImage}, {"/rgb/camera_info", kInfo}});
  EXPECT_EQ(k4a.recorder, "Azure Kinect ROS driver");
  EXPECT_EQ(k4a.rgb, "/rgb/image_raw");
  const ros1::BagRecording tum = recorded({{"/camera/rgb/image_color", kImage}, {"/camera/depth/image", kImage},
                                           {"/camera/rgb/camera_info", kInfo}, {"/tf", "tf/tfMessage"}});
  EXPECT_EQ(tum.recorder, "TUM RGB-D");
  EXPECT_TRUE(tum.registered_by.empty());  // registered, but nobody says so: the run checks the images
}

TEST(RosBagRecordings, NothingKnownOrTwoCamerasIsSaidWithTheTopics) {
  const std::string none = error_of({{"/cam/left", kImage}, {"/cam/right", kImage}});
  EXPECT_NE(none.find("the bag's sensor_msgs/Image topics: /cam/left, /cam/right; pass --rgb-topic and --depth-topic"),
            std::string::npos)
      << none;
  const std::string two = error_of({{"/front/color/image_raw", kImage},
                                    {"/front/aligned_depth_to_color/image_raw", kImage},
                                    {"/down/color/image_raw", kImage},
                                    {"/down/aligned_depth_to_color/image_raw", kImage}});
  EXPECT_NE(two.find("2 colour/depth pairs"), std::string::npos) << two;
  EXPECT_NE(two.find("/down/color/image_raw + /down/aligned_depth_to_color/image_raw"), std::string::npos) << two;
  EXPECT_NE(two.find("/front/color/image_raw"), std::string::npos) << two;
}

// A rig of two RealSense cameras recorded without align_depth, one of them without its depth
// CameraInfo: recognition alone cannot choose (and stops at the incomplete one); topics given for
// the complete camera get its raw depth's CameraInfo, as without topic options, and the other
// camera's missing topic does not matter.
TEST(RosBagRecordings, TopicsGivenForOneCameraOfARigKeepItsRecordersTopics) {
  const Topics rig = {{"/front/color/image_raw", kImage},    {"/front/color/camera_info", kInfo},
                      {"/front/depth/image_rect_raw", kImage}, {"/front/depth/camera_info", kInfo},
                      {"/down/color/image_raw", kImage},     {"/down/color/camera_info", kInfo},
                      {"/down/depth/image_rect_raw", kImage},  {"/tf_static", "tf2_msgs/TFMessage"}};
  EXPECT_NE(error_of(rig).find("without /down/depth/camera_info"), std::string::npos) << error_of(rig);
  const auto front = ros1::recording_with(rig, "/front/color/image_raw", "/front/depth/image_rect_raw");
  ASSERT_TRUE(front);
  EXPECT_EQ(front->depth_info, "/front/depth/camera_info");
  EXPECT_EQ(front->rgb_info, "/front/color/camera_info");
  EXPECT_FALSE(front->registered());
  EXPECT_EQ(front->recorder, "realsense2_camera (ROS), depth not aligned");
  EXPECT_THROW(ros1::recording_with(rig, "/down/color/image_raw", "/down/depth/image_rect_raw"), Error);
  EXPECT_FALSE(ros1::recording_with(rig, "/front/color/image_raw", "/down/depth/image_rect_raw"));
  EXPECT_FALSE(ros1::recording_with(rig, "/cam/left", "/cam/depth"));
}

TEST(RosConversions, KinectBayerColourIsDebayered) {
  // A 2x2 GRBG tile: G R / B G. cv_bridge's debayering gives every pixel all three channels.
  sensor_msgs::Image msg;
  msg.width = 4, msg.height = 4, msg.step = 4, msg.encoding = "bayer_grbg8";
  for (int v = 0; v < 4; ++v)
    for (int u = 0; u < 4; ++u) msg.data.push_back(v % 2 == 0 ? (u % 2 == 0 ? 100 : 200) : (u % 2 == 0 ? 50 : 100));
  const cv::Mat bgr = ros1::colour_to_bgr(msg);
  ASSERT_EQ(bgr.type(), CV_8UC3);
  const cv::Vec3b centre = bgr.at<cv::Vec3b>(1, 1);  // a green site between red and blue ones
  EXPECT_EQ(centre[0], 50);   // blue
  EXPECT_EQ(centre[1], 100);  // green
  EXPECT_EQ(centre[2], 200);  // red
}

TEST(RosConversions, InverseBrownConradyBecomesForwardCoefficients) {
  // A D455 colour stream's kind of coefficients (they undo the distortion: distorted -> undistorted).
  sensor_msgs::CameraInfo info;
  info.width = 1280, info.height = 720;
  info.K = {640, 0, 641.2, 0, 639.5, 362.7, 0, 0, 1};
  info.distortion_model = "Inverse Brown Conrady";
  const std::vector<double> c{-0.0556, 0.0646, -0.0004, 0.0009, -0.0208};
  info.D = c;
  const PinholeCamera cam = ros1::camera_from_info(info, 40.0);
  // Every distorted pixel, undone with the SDK's formula and projected with OpenCV's forward model
  // and the fitted coefficients, comes back to itself.
  std::vector<cv::Point3d> undistorted;
  std::vector<cv::Point2d> pixels;
  for (double u = 0; u < 1280; u += 71)
    for (double v = 0; v < 720; v += 53) {
      const double x = (u - 641.2) / 640, y = (v - 362.7) / 639.5, r2 = x * x + y * y;
      const double f = 1 + c[0] * r2 + c[1] * r2 * r2 + c[4] * r2 * r2 * r2;
      undistorted.emplace_back(x * f + 2 * c[2] * x * y + c[3] * (r2 + 2 * x * x),
                               y * f + 2 * c[3] * x * y + c[2] * (r2 + 2 * y * y), 1.0);
      pixels.emplace_back(u, v);
    }
  std::vector<cv::Point2d> projected;
  cv::projectPoints(undistorted, cv::Vec3d(0, 0, 0), cv::Vec3d(0, 0, 0),
                    cv::Matx33d(640, 0, 641.2, 0, 639.5, 362.7, 0, 0, 1),
                    std::vector<double>(cam.dist.begin(), cam.dist.end()), projected);
  double worst = 0;
  for (std::size_t i = 0; i < pixels.size(); ++i) worst = std::max(worst, cv::norm(projected[i] - pixels[i]));
  EXPECT_LT(worst, 0.1) << "px";
  EXPECT_GT(cam.dist[0], 0.03);  // forward k1 has the opposite sign of the inverse one
  sensor_msgs::CameraInfo zeros = info;
  zeros.D.assign(5, 0.0);
  EXPECT_FALSE(ros1::camera_from_info(zeros, 40.0).has_distortion());  // a D435's colour stream
  zeros.distortion_model = "Kannala Brandt4";
  EXPECT_FALSE(ros1::camera_from_info(zeros, 40.0).has_distortion());  // no coefficients: any name
  info.distortion_model = "Kannala Brandt4";
  EXPECT_THROW(ros1::camera_from_info(info, 40.0), Error);
}

TEST(RosConversions, LiveNodeTakesTheDriversCalibrationUnlessTold) {
  PinholeCamera c;
  c.fx = c.fy = 615.2, c.cx = 322.1, c.cy = 241.9;
  sensor_msgs::CameraInfo info = ros1::info_from_camera(c);
  std::string note;
  // realsense_d455.yaml's camera file is another unit's: the driver's CameraInfo is used.
  const std::string preset_camera = std::string(S3M_SOURCE_DIR) + "/config/cameras/realsense_d455_640x480.yaml";
  EXPECT_DOUBLE_EQ(ros1::live_camera(info, preset_camera, false, 40, note).fx, 615.2);
  EXPECT_EQ(note, "camera from the CameraInfo (640x480, fx 615.2); the config's dataset.camera " + preset_camera +
                      " is not used (~camera_from_config:=true uses it)");
  const double preset_fx = io::load_camera(preset_camera).fx;
  EXPECT_DOUBLE_EQ(ros1::live_camera(info, preset_camera, true, 40, note).fx, preset_fx);
  EXPECT_NE(note.find(", ~camera_from_config; the CameraInfo says 640x480, fx 615.2"), std::string::npos) << note;
  info.K = {0, 0, 0, 0, 0, 0, 0, 0, 0};  // an uncalibrated driver's empty CameraInfo
  EXPECT_DOUBLE_EQ(ros1::live_camera(info, preset_camera, false, 40, note).fx, preset_fx);
  EXPECT_NE(note.find("the CameraInfo has no intrinsics"), std::string::npos) << note;
  EXPECT_THROW(ros1::live_camera(info, "", true, 40, note), Error);
}

}  // namespace
}  // namespace s3m
