// Bags as camera drivers and recorders write them (bag_recordings.hpp): recognised by their topics,
// raw depth drawn into the colour camera with the recorded extrinsics, the RealSense SDK's depth
// unit and distortion model. The SDK and realsense2_camera bags here are written from a simulated
// flight with a separate depth camera (848x480, 1.5 cm beside the colour camera, slightly turned),
// so what `s3m run --rosbag` makes of them is compared with the flight's exact depth and poses.
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <string>

#include <cv_bridge/cv_bridge.h>
#include <gtest/gtest.h>
#include <geometry_msgs/TransformStamped.h>
#include <opencv2/calib3d.hpp>
#include <opencv2/imgproc.hpp>
#include <rosbag/bag.h>
#include <std_msgs/Float32.h>
#include <tf2_msgs/TFMessage.h>

#include "bag_recordings.hpp"
#include "bag_source.hpp"
#include "../integration/depth_agreement.hpp"
#include "conversions.hpp"
#include "ros_test_util.hpp"
#include "s3m/core/error.hpp"
#include "s3m/eval/trajectory_eval.hpp"
#include "s3m/io/camera_yaml.hpp"
#include "s3m/io/depth_to_colour.hpp"
#include "s3m/io/trajectory.hpp"
#include "s3m/io/tum_dataset.hpp"
#include "s3m/sim/simulate.hpp"

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

// ---- Bags written from a simulated flight, as a RealSense would record it --------------------

struct Flight {
  fs::path dir, seq;
  PinholeCamera colour, depth;  // depth: the D4xx-like depth camera beside the colour camera
  SE3 T_c_d;
};

const Flight& flight() {
  static const Flight f = [] {
    Flight out;
    out.dir = fs::temp_directory_path() / ("s3m_ros_recordings_" + std::to_string(::getpid()));
    fs::remove_all(out.dir);
    fs::create_directories(out.dir);
    sim::SimConfig c;
    c.scene = "office";
    c.seed = 7;
    c.trajectory.type = "handheld";
    c.trajectory.frames = 40;
    out.seq = out.dir / "seq";
    sim::simulate_sequence(c, out.seq.string());
    out.colour = io::TumDataset::open(out.seq.string()).camera();
    out.depth.fx = out.depth.fy = 425, out.depth.cx = 423.5, out.depth.cy = 239.5;
    out.depth.width = 848, out.depth.height = 480;
    out.T_c_d = make_se3(Vec3(-0.015, 0.0003, 0.0002), Quat(Eigen::AngleAxisd(0.006, Vec3(0.3, 1, 0.2).normalized())));
    return out;
  }();
  return f;
}

sensor_msgs::Image mono16_depth(const cv::Mat& depth_m, double metres_per_unit, const std::string& encoding) {
  cv::Mat units(depth_m.size(), CV_16UC1);
  depth_m.convertTo(units, CV_16U, 1.0 / metres_per_unit);  // rounds; 0 stays 0
  return *cv_bridge::CvImage(std_msgs::Header(), encoding, units).toImageMsg();
}

sensor_msgs::CameraInfo info(const PinholeCamera& c, const std::string& model, const std::string& frame) {
  sensor_msgs::CameraInfo i = ros1::info_from_camera(c);
  i.distortion_model = model;
  i.P[3] = 0;  // a driver's CameraInfo carries no virtual stereo term
  i.header.frame_id = frame;
  return i;
}

// Writes every frame of the flight: colour as recorded, depth seen from the depth camera.
template <typename WriteFrame>
void write_frames(const Flight& f, WriteFrame write_frame) {
  const io::TumDataset ds = io::TumDataset::open(f.seq.string());
  const io::DepthToColour to_depth_camera(f.colour, f.depth, f.T_c_d.inverse());
  for (std::size_t i = 0; i < ds.size(); ++i) {
    const RgbdFrame fr = ds.load(i);
    write_frame(ros1::to_ros_time(fr.t_s), ros1::bgr_to_msg(fr.rgb), to_depth_camera(fr.depth_m));
  }
}

fs::path realsense_sdk_bag(const Flight& f) {
  const fs::path bag = f.dir / "realsense_sdk.bag";
  const std::string colour = "/device_0/sensor_1/Color_0", depth = "/device_0/sensor_0/Depth_0";
  const double unit = 0.0005;  // not the default 1 mm: a run that ignored it would see everything halved
  rosbag::Bag b(bag.string(), rosbag::bagmode::Write);
  const ros::Time t0(1.0);
  b.write(colour + "/info/camera_info", t0, info(f.colour, "Inverse Brown Conrady", ""));
  b.write(depth + "/info/camera_info", t0, info(f.depth, "Brown Conrady", ""));
  std_msgs::Float32 units;
  units.data = static_cast<float>(unit);
  b.write("/device_0/sensor_0/option/Depth Units/value", t0, units);
  // Extrinsics from the reference stream (the depth stream, group 0) into each stream.
  b.write(depth + "/tf/0", t0, ros1::to_transform(SE3::Identity()));
  b.write(colour + "/tf/0", t0, ros1::to_transform(f.T_c_d));
  write_frames(f, [&](const ros::Time& t, sensor_msgs::Image rgb, const cv::Mat& depth_m) {
    sensor_msgs::Image d = mono16_depth(depth_m, unit, "mono16");
    rgb.header.stamp = d.header.stamp = t;
    b.write(colour + "/image/data", t, rgb);
    b.write(depth + "/image/data", t, d);
  });
  return bag;
}

fs::path realsense_ros_raw_bag(const Flight& f) {
  const fs::path bag = f.dir / "realsense_ros_raw.bag";
  rosbag::Bag b(bag.string(), rosbag::bagmode::Write);
  const ros::Time t0(1.0);
  const std::string colour_frame = "camera_color_optical_frame", depth_frame = "camera_depth_optical_frame";
  // The driver's static frames: both optical frames hang off camera_link.
  const SE3 T_link_c = make_se3(Vec3(0, 0.015, 0), Quat(0.5, -0.5, 0.5, -0.5));
  tf2_msgs::TFMessage statics;
  for (const auto& [child, T] : {std::pair{colour_frame, T_link_c}, std::pair{depth_frame, SE3(T_link_c * f.T_c_d)}}) {
    geometry_msgs::TransformStamped ts;
    ts.header.stamp = t0, ts.header.frame_id = "camera_link", ts.child_frame_id = child;
    ts.transform = ros1::to_transform(T);
    statics.transforms.push_back(ts);
  }
  b.write("/tf_static", t0, statics);
  b.write("/camera/color/camera_info", t0, info(f.colour, "plumb_bob", colour_frame));
  b.write("/camera/depth/camera_info", t0, info(f.depth, "plumb_bob", depth_frame));
  write_frames(f, [&](const ros::Time& t, sensor_msgs::Image rgb, const cv::Mat& depth_m) {
    sensor_msgs::Image d = mono16_depth(depth_m, 0.001, "16UC1");
    rgb.header.stamp = d.header.stamp = t;
    b.write("/camera/color/image_raw", t, rgb);
    b.write("/camera/depth/image_rect_raw", t, d);
  });
  return bag;
}

// Depth read from the bag (aligned to colour here) against the flight's own colour-registered depth.
void expect_depth_like_the_flight(const fs::path& bag, double quantum_m) {
  const Flight& f = flight();
  const auto source = ros1::open_bag_source(bag.string(), ros1::BagTopics{"", "", "", "", ""}, pipeline::DatasetConfig{});
  const io::TumDataset ds = io::TumDataset::open(f.seq.string());
  ASSERT_EQ(source->size(), ds.size());
  EXPECT_DOUBLE_EQ(source->camera().fx, f.colour.fx);
  EXPECT_EQ(source->camera().width, f.colour.width);
  for (std::size_t i : {5u, 30u}) {
    const cv::Mat truth = ds.load(i).depth_m, got = source->load(i).depth_m;
    ASSERT_EQ(got.size(), truth.size());
    const auto [valid, close, missing, invented] = s3m::testing::depth_agreement(truth, got, quantum_m);
    std::cout << bag.filename().string() << " frame " << i << ": " << close << " of " << valid
              << " within the 3x3 range, missing " << missing << ", invented " << invented << "\n";
    EXPECT_GT(valid, 200000);
    EXPECT_GE(static_cast<double>(close) / valid, 0.99) << "frame " << i;
    EXPECT_LE(invented, valid / 100) << "frame " << i;
  }
}

TEST(RosBagRecordings, RealSenseSdkBagIsAlignedToColourWithItsUnit) {
  expect_depth_like_the_flight(realsense_sdk_bag(flight()), 0.0005);
}

TEST(RosBagRecordings, RealsenseRosRawDepthIsPlacedByTfStatic) {
  expect_depth_like_the_flight(realsense_ros_raw_bag(flight()), 0.001);
}

TEST(RosBagRecordings, TheDevicesCalibrationWinsOverAPresetsCameraUnlessToldOtherwise) {
  const Flight& f = flight();
  const fs::path bag = f.dir / "realsense_sdk.bag";
  if (!fs::exists(bag)) realsense_sdk_bag(f);
  const ros1::BagTopics recognised{"", "", "", "", ""}, config_camera{"", "", "none", "", ""};
  pipeline::DatasetConfig preset;
  preset.camera = "tum_fr1";  // 640x480 like the flight, another focal length
  EXPECT_DOUBLE_EQ(ros1::open_bag_source(bag.string(), recognised, preset)->camera().fx, f.colour.fx);
  EXPECT_NEAR(ros1::open_bag_source(bag.string(), config_camera, preset)->camera().fx, 517.3, 0.1);
  const fs::path small = f.dir / "camera_320.yaml";
  std::ofstream(small) << "fx: 262.5\nfy: 262.5\ncx: 159.5\ncy: 119.5\nwidth: 320\nheight: 240\ndepth_factor: 1000\n";
  preset.camera = small.string();
  try {
    ros1::open_bag_source(bag.string(), config_camera, preset);
    ADD_FAILURE() << "a 320x240 camera was accepted for 640x480 images";
  } catch (const Error& e) {
    const std::string m = e.what();
    EXPECT_NE(m.find("the colour images are 640x480 but the camera (dataset.camera " + small.string() + ") is 320x240"),
              std::string::npos)
        << m;
  }
  preset.camera = "";
  EXPECT_THROW(ros1::open_bag_source(bag.string(), config_camera, preset), Error);  // none, and no config camera
}

double ate_cm(const fs::path& run_dir) {
  const io::Trajectory gt = io::TumDataset::open(flight().seq.string()).groundtruth();
  const io::Trajectory est = io::read_tum_trajectory((run_dir / "trajectory_camera.txt").string());
  return eval::evaluate_trajectory(gt, est).ate.stats_m.rmse * 100;
}

int run(const std::string& cmd, const fs::path& log) {
  return std::system((cmd + " > " + log.string() + " 2>&1").c_str());
}

TEST(RosBagRecordings, RealSenseSdkBagRunsWithoutTopicOptions) {
  // What a user with a RealSense types: the bag and nothing about its topics, units or extrinsics.
  const Flight& f = flight();
  const fs::path bag = f.dir / "realsense_sdk.bag";
  if (!fs::exists(bag)) realsense_sdk_bag(f);
  // The bag with the RealSense preset, as its user would (its camera file is not the device's:
  // the recording's calibration is used); the directory with the simulator's own preset.
  const std::string s3m = S3M_BINARY, config = std::string(S3M_SOURCE_DIR) + "/config/",
                    common = " --slam-only --deterministic --no-report --out ";
  ASSERT_EQ(run(s3m + " run " + f.seq.string() + " --config " + config + "sim.yaml" + common + (f.dir / "dir_run").string(),
                f.dir / "dir.log"),
            0)
      << rostest::read_file(f.dir / "dir.log");
  ASSERT_EQ(run(s3m + " run --rosbag " + bag.string() + " --config " + config + "realsense_d455.yaml" + common +
                    (f.dir / "bag_run").string(),
                f.dir / "bag.log"),
            0)
      << rostest::read_file(f.dir / "bag.log");
  const std::string log = rostest::read_file(f.dir / "bag.log");
  EXPECT_NE(log.find("RealSense SDK (realsense-viewer, rs-record)"), std::string::npos) << log;
  EXPECT_NE(log.find("depth camera 848x480 fx 425.0, 1.5 cm from the colour camera"), std::string::npos) << log;
  EXPECT_NE(log.find("camera from the recording's CameraInfo (/device_0/sensor_1/Color_0/info/camera_info), not the "
                     "config's dataset.camera"),
            std::string::npos)
      << log;
  EXPECT_NE(log.find("registered (aligned to colour by s3m"), std::string::npos) << log;
  const double from_dir = ate_cm(f.dir / "dir_run"), from_bag = ate_cm(f.dir / "bag_run");
  std::cout << "ATE: directory (registered depth) " << from_dir << " cm, RealSense SDK bag (raw depth aligned here) "
            << from_bag << " cm\n";
  EXPECT_LT(from_bag, std::max(1.5 * from_dir, from_dir + 0.5));
}

TEST(RosBagRecordings, CheckSaysWhatARunWouldMakeOfTheBag) {
  const Flight& f = flight();
  const fs::path bag = f.dir / "realsense_sdk.bag";
  if (!fs::exists(bag)) realsense_sdk_bag(f);
  ASSERT_EQ(run(std::string(S3M_BINARY) + " check --rosbag " + bag.string(), f.dir / "check.log"), 0)
      << rostest::read_file(f.dir / "check.log");
  const std::string out = rostest::read_file(f.dir / "check.log");
  for (const std::string& line :
       {"dataset: " + bag.string() + " (ROS bag, RealSense SDK (realsense-viewer, rs-record): colour "
        "/device_0/sensor_1/Color_0/image/data, depth /device_0/sensor_0/Depth_0/image/data (aligned to colour here, "
        "depth unit 0.5 mm))",
        std::string("frames: 40, t "), std::string("(from CameraInfo on /device_0/sensor_1/Color_0/info/camera_info)"),
        std::string("ground truth: none"),
        // Aligned by the reader: the run skips the image-based check (which would measure the
        // alignment's own resampling, not a misregistration).
        std::string("depth: registered (aligned to colour by s3m, with the recording's depth camera and extrinsics)")})
    EXPECT_NE(out.find(line), std::string::npos) << line << "\n" << out;
}

// The flight and its bags are made once per test process; removed at its end.
class RemoveFlight : public ::testing::Environment {
 public:
  void TearDown() override {
    const fs::path dir = fs::temp_directory_path() / ("s3m_ros_recordings_" + std::to_string(::getpid()));
    fs::remove_all(dir);
  }
};
const auto* const kRemoveFlight = ::testing::AddGlobalTestEnvironment(new RemoveFlight);

}  // namespace
}  // namespace s3m
