// Bags as camera drivers and recorders write them, from a simulated flight with a separate depth
// camera (848x480, 1.5 cm beside the colour camera, slightly turned): raw depth drawn into the
// colour camera with the recorded extrinsics, the RealSense SDK's depth unit, the camera
// precedence, `s3m check --rosbag`; what `s3m run --rosbag` makes of them is compared with the
// flight's exact depth and poses. Recognition from topic tables alone: ros_bag_recogniser_test.cpp.
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

// namespaces: one realsense2_camera per namespace, each recording the same flight (a rig); the
// cameras after the first are decoys whose /tf_static places their depth camera wrongly (T_c_d
// reversed), so a reader that took another camera's extrinsics fails the depth check.
fs::path realsense_ros_raw_bag(const Flight& f, const std::vector<std::string>& namespaces = {"/camera"}) {
  const fs::path bag = f.dir / ("realsense_ros_raw_" + std::to_string(namespaces.size()) + ".bag");
  rosbag::Bag b(bag.string(), rosbag::bagmode::Write);
  const ros::Time t0(1.0);
  // The driver's static frames: both optical frames hang off camera_link.
  const SE3 T_link_c = make_se3(Vec3(0, 0.015, 0), Quat(0.5, -0.5, 0.5, -0.5));
  tf2_msgs::TFMessage statics;
  for (std::size_t i = 0; i < namespaces.size(); ++i) {
    const std::string name = namespaces[i].substr(1), colour_frame = name + "_color_optical_frame",
                      depth_frame = name + "_depth_optical_frame";
    const SE3 T_c_d = i == 0 ? f.T_c_d : SE3(f.T_c_d.inverse());
    for (const auto& [child, T] : {std::pair{colour_frame, T_link_c}, std::pair{depth_frame, SE3(T_link_c * T_c_d)}}) {
      geometry_msgs::TransformStamped ts;
      ts.header.stamp = t0, ts.header.frame_id = name + "_link", ts.child_frame_id = child;
      ts.transform = ros1::to_transform(T);
      statics.transforms.push_back(ts);
    }
    b.write(namespaces[i] + "/color/camera_info", t0, info(f.colour, "plumb_bob", colour_frame));
    b.write(namespaces[i] + "/depth/camera_info", t0, info(f.depth, "plumb_bob", depth_frame));
  }
  b.write("/tf_static", t0, statics);
  write_frames(f, [&](const ros::Time& t, sensor_msgs::Image rgb, const cv::Mat& depth_m) {
    sensor_msgs::Image d = mono16_depth(depth_m, 0.001, "16UC1");
    rgb.header.stamp = d.header.stamp = t;
    for (const std::string& ns : namespaces) {
      b.write(ns + "/color/image_raw", t, rgb);
      b.write(ns + "/depth/image_rect_raw", t, d);
    }
  });
  return bag;
}

// Depth read from the bag (aligned to colour here) against the flight's own colour-registered depth.
void expect_depth_like_the_flight(const fs::path& bag, double quantum_m,
                                  const ros1::BagTopics& topics = ros1::BagTopics{"", "", "", "", ""}) {
  const Flight& f = flight();
  const auto source = ros1::open_bag_source(bag.string(), topics, pipeline::DatasetConfig{});
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

TEST(RosBagRecordings, OneCameraOfARigChosenByTopicsIsAlignedWithItsOwnExtrinsics) {
  // Two cameras: without topic options the reader cannot choose; with /front's topics it aligns
  // /front's raw depth with /front's CameraInfo and /tf_static frames (/down's are wrong on purpose).
  const fs::path bag = realsense_ros_raw_bag(flight(), {"/front", "/down"});
  try {
    ros1::open_bag_source(bag.string(), ros1::BagTopics{"", "", "", "", ""}, pipeline::DatasetConfig{});
    ADD_FAILURE() << "a bag of two cameras was read without topics";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("2 colour/depth pairs"), std::string::npos) << e.what();
  }
  expect_depth_like_the_flight(bag, 0.001,
                               ros1::BagTopics{"/front/color/image_raw", "/front/depth/image_rect_raw", "", "", ""});
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
  EXPECT_NE(log.find("depth camera 848x480 fx 425.0 at (-1.50, 0.03, 0.02) cm in the colour camera; its depth is "
                     "drawn into the colour camera's 640x480 pixels"), std::string::npos) << log;
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
        std::string("depth: registered (aligned to colour by s3m, with the recording's depth camera and extrinsics)"),
        // The depth camera on a line of its own (log lines start with their time).
        std::string("\ndepth camera 848x480 fx 425.0 at (-1.50, 0.03, 0.02) cm in the colour camera; its depth is "
                    "drawn into the colour camera's 640x480 pixels\n")})
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
