// ROS1 conversions (hand-computed values) and the rosbag round trip of the acceptance criteria:
// TUM dir -> `s3m tum2bag` -> `s3m run --rosbag --deterministic` gives byte-identical trajectory,
// keyframes and map to `s3m run DIR --deterministic`. No ROS master needed.
#include <cstdlib>
#include <filesystem>
#include <string>

#include <gtest/gtest.h>
#include <sensor_msgs/image_encodings.h>

#include <rosbag/bag.h>

#include "bag_source.hpp"
#include "conversions.hpp"
#include "ros_params.hpp"
#include "ros_test_util.hpp"
#include "s3m/core/error.hpp"
#include "s3m/io/camera_yaml.hpp"
#include "s3m/io/tum_dataset.hpp"
#include "s3m/sim/simulate.hpp"

namespace s3m {
namespace {

namespace fs = std::filesystem;
namespace enc = sensor_msgs::image_encodings;

TEST(RosConversions, Depth16UC1IsMillimetresAnd32FC1Metres) {
  cv::Mat mm(2, 2, CV_16UC1);
  mm.at<std::uint16_t>(0, 0) = 0, mm.at<std::uint16_t>(0, 1) = 1500;
  mm.at<std::uint16_t>(1, 0) = 65535, mm.at<std::uint16_t>(1, 1) = 1;
  cv::Mat m(2, 2, CV_32FC1);
  mm.convertTo(m, CV_32F, 1e-3);
  const cv::Mat from16 = ros1::depth_to_metres(ros1::depth_to_msg(m, enc::TYPE_16UC1));
  EXPECT_FLOAT_EQ(from16.at<float>(0, 0), 0.0f);  // no measurement stays 0
  EXPECT_FLOAT_EQ(from16.at<float>(0, 1), 1.5f);
  EXPECT_FLOAT_EQ(from16.at<float>(1, 0), 65.535f);
  EXPECT_FLOAT_EQ(from16.at<float>(1, 1), 0.001f);
  const cv::Mat from32 = ros1::depth_to_metres(ros1::depth_to_msg(m, enc::TYPE_32FC1));
  EXPECT_EQ(cv::countNonZero(from32 != m), 0);  // 32FC1 is bit-exact
}

TEST(RosConversions, ColourComesBackAsBgrAndBadEncodingsAreNamed) {
  cv::Mat bgr(1, 2, CV_8UC3, cv::Scalar(10, 20, 30));
  const sensor_msgs::Image msg = ros1::bgr_to_msg(bgr);
  EXPECT_EQ(msg.encoding, "rgb8");
  EXPECT_EQ(msg.data[0], 30);  // red first on the wire
  const cv::Mat back = ros1::colour_to_bgr(msg);
  EXPECT_EQ(back.at<cv::Vec3b>(0, 1), cv::Vec3b(10, 20, 30));
  sensor_msgs::Image bad = msg;
  bad.encoding = "yuv422";
  try {
    ros1::colour_to_bgr(bad);
    FAIL() << "yuv422 accepted";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("yuv422"), std::string::npos) << e.what();
  }
}

TEST(RosConversions, CameraInfoRoundTripKeepsIntrinsicsDistortionAndBf) {
  PinholeCamera c;
  c.fx = 500, c.fy = 510, c.cx = 319, c.cy = 241, c.width = 640, c.height = 480, c.bf = 37.5;
  c.dist = {0.1, -0.2, 0.001, 0.002, 0.03};
  const sensor_msgs::CameraInfo info = ros1::info_from_camera(c);
  EXPECT_DOUBLE_EQ(info.P[3], -37.5);  // a right stereo camera's Tx = -fx * B
  const PinholeCamera back = ros1::camera_from_info(info, 99.0);
  EXPECT_DOUBLE_EQ(back.fx, 500);
  EXPECT_DOUBLE_EQ(back.fy, 510);
  EXPECT_DOUBLE_EQ(back.cx, 319);
  EXPECT_DOUBLE_EQ(back.cy, 241);
  EXPECT_EQ(back.width, 640);
  EXPECT_DOUBLE_EQ(back.bf, 37.5);
  EXPECT_DOUBLE_EQ(back.dist[4], 0.03);
  sensor_msgs::CameraInfo mono = info;
  mono.P[3] = 0;  // a plain driver's CameraInfo: bf from the default
  EXPECT_DOUBLE_EQ(ros1::camera_from_info(mono, 99.0).bf, 99.0);
}

TEST(RosConversions, TumStampsSurviveRosTime) {
  for (double t : {1.0, 1.033333, 1305031102.175304, 1305031102.211214})
    EXPECT_EQ(ros1::to_seconds(ros1::to_ros_time(t)), t) << t;
}

// One short simulated flight, rendered per test process (fixed seed).
fs::path sequence(const fs::path& dir) {
  sim::SimConfig c;
  c.scene = "office";
  c.seed = 7;
  c.trajectory.type = "handheld";
  c.trajectory.frames = 40;
  const fs::path seq = dir / "seq";
  sim::simulate_sequence(c, seq.string());
  return seq;
}

int run(const std::string& cmd, const fs::path& log) {
  return std::system((cmd + " > " + log.string() + " 2>&1").c_str());
}

TEST(RosBag, RoundTripGivesTheSameTrajectoryAndMapAsTheDirectory) {
  const fs::path dir = fs::temp_directory_path() / ("s3m_ros_bag_" + std::to_string(::getpid()));
  fs::remove_all(dir);
  fs::create_directories(dir);
  const fs::path seq = sequence(dir);
  const std::string s3m = S3M_BINARY, preset = std::string(S3M_SOURCE_DIR) + "/config/sim.yaml";
  const fs::path bag = dir / "seq.bag";
  ASSERT_EQ(run(s3m + " tum2bag " + seq.string() + " --out " + bag.string(), dir / "tum2bag.log"), 0)
      << rostest::read_file(dir / "tum2bag.log");
  const std::string common = " --config " + preset + " --segmenter oracle --deterministic --no-report";
  ASSERT_EQ(run(s3m + " run " + seq.string() + " --out " + (dir / "from_dir").string() + common, dir / "a.log"), 0)
      << rostest::read_file(dir / "a.log");
  ASSERT_EQ(run(s3m + " run --rosbag " + bag.string() + " --labels-topic /camera/labels --out " +
                    (dir / "from_bag").string() + common,
                dir / "b.log"),
            0)
      << rostest::read_file(dir / "b.log");
  for (const char* f : {"trajectory_camera.txt", "trajectory_robot.txt", "keyframes.txt", "map.ply"}) {
    const std::string a = rostest::read_file(dir / "from_dir" / f), b = rostest::read_file(dir / "from_bag" / f);
    EXPECT_FALSE(a.empty()) << f;
    EXPECT_TRUE(a == b) << f << " differs between the directory and the bag run";
  }
  // 40 frames, all of them read from the bag.
  std::size_t lines = 0;
  for (char ch : rostest::read_file(dir / "from_bag" / "trajectory_camera.txt")) lines += ch == '\n';
  EXPECT_GE(lines, 40u);
  // The bag's ground-truth topic feeds metrics.json like groundtruth.txt does.
  EXPECT_NE(rostest::read_file(dir / "from_bag" / "metrics.json").find("ate_rmse_m"), std::string::npos);
  fs::remove_all(dir);
}

TEST(RosBag, AConfigCameraWithADepthCameraAlignsTheBagsDepth) {
  // A 7-Scenes folder written as a bag has TUM's topics, which name depth registered to colour; the
  // config's camera (7scenes_kinect_v1, or a file with a depth_camera section) says it is not.
  const fs::path dir = fs::temp_directory_path() / ("s3m_ros_bag_rig_" + std::to_string(::getpid()));
  fs::remove_all(dir);
  fs::create_directories(dir);
  const fs::path seq = sequence(dir), bag = dir / "seq.bag";
  ASSERT_EQ(run(std::string(S3M_BINARY) + " tum2bag " + seq.string() + " --out " + bag.string(), dir / "tum2bag.log"), 0)
      << rostest::read_file(dir / "tum2bag.log");
  const PinholeCamera cam = io::TumDataset::open(seq.string()).camera();
  const fs::path plain = dir / "plain.yaml", rig = dir / "rig.yaml";
  io::write_camera_yaml(plain.string(), cam);
  io::write_camera_yaml(rig.string(), cam, io::DepthCamera{cam, SE3::Identity()});  // the same camera, 0 cm apart
  pipeline::DatasetConfig as_plain, as_rig;
  as_plain.camera = plain.string(), as_rig.camera = rig.string();
  ros1::BagTopics topics;
  topics.camera_info = "";  // as `s3m run --rosbag` without --camera-info-topic: the config's camera
  const auto from_plain = ros1::open_bag_source(bag.string(), topics, as_plain);
  const auto from_rig = ros1::open_bag_source(bag.string(), topics, as_rig);
  EXPECT_EQ(from_plain->depth_registered_by(), "") << from_plain->depth_registered_by();  // topics given: not known
  EXPECT_EQ(from_rig->depth_registered_by(), "s3m, with the depth_camera of dataset.camera " + rig.string());
  EXPECT_NE(from_rig->depth_camera().find("depth camera 640x480"), std::string::npos) << from_rig->depth_camera();
  // A depth camera identical to the colour camera: each depth pixel's patch holds exactly its own
  // colour pixel's centre, at its own depth, so the depth comes back bit for bit.
  for (std::size_t i : {0u, 20u}) {
    const cv::Mat a = from_plain->load(i).depth_m, b = from_rig->load(i).depth_m;
    ASSERT_EQ(a.size(), b.size());
    EXPECT_EQ(cv::countNonZero(a != b), 0) << "frame " << i;
  }
  fs::remove_all(dir);
}

TEST(RosBag, MissingTopicIsNamed) {
  const fs::path dir = fs::temp_directory_path() / ("s3m_ros_bag_topic_" + std::to_string(::getpid()));
  fs::remove_all(dir);
  fs::create_directories(dir);
  const fs::path bag = dir / "empty.bag";
  // A recorder's own topic names (a RealSense bag's): the error lists the bag's image topics with
  // their message counts, so the user can pass them without `rosbag info`.
  const std::string colour = "/device_0/sensor_1/Color_0/image/data", depth = "/device_0/sensor_0/Depth_0/image/data";
  {
    rosbag::Bag b(bag.string(), rosbag::bagmode::Write);
    for (int i = 0; i < 3; ++i)
      b.write(colour, ros::Time(1.0 + i), ros1::bgr_to_msg(cv::Mat(2, 2, CV_8UC3, cv::Scalar::all(0))));
    b.write(depth, ros::Time(1.0), ros1::depth_to_msg(cv::Mat(2, 2, CV_32FC1, cv::Scalar::all(1.0f)), "16UC1"));
  }
  const auto error = [&](const ros1::BagTopics& topics) {
    try {
      ros1::open_bag_source(bag.string(), topics, pipeline::DatasetConfig{});
    } catch (const Error& e) {
      return std::string(e.what());
    }
    ADD_FAILURE() << "a bag without the topic was accepted";
    return std::string();
  };
  const std::string no_colour = error(ros1::BagTopics{});
  EXPECT_NE(no_colour.find("no messages on the colour topic /camera/rgb/image_color (--rgb-topic)"), std::string::npos)
      << no_colour;
  EXPECT_NE(no_colour.find("its sensor_msgs/Image topics (messages): " + depth + " (1), " + colour + " (3)"),
            std::string::npos)
      << no_colour;
  // Those topics named: they are the RealSense SDK's, whose raw depth needs its CameraInfo.
  ros1::BagTopics named;
  named.rgb = colour;
  named.depth = depth;
  const std::string no_depth_info = error(named);
  EXPECT_NE(no_depth_info.find("RealSense SDK bag: no /device_0/sensor_0/Depth_0/info/camera_info (the depth "
                               "camera's intrinsics"),
            std::string::npos)
      << no_depth_info;
  // Topics no recorder wrote, named, without the camera-info topic given: that topic is named.
  {
    rosbag::Bag b(bag.string(), rosbag::bagmode::Write);
    b.write("/cam/rgb", ros::Time(1.0), ros1::bgr_to_msg(cv::Mat(2, 2, CV_8UC3, cv::Scalar::all(0))));
    b.write("/cam/depth", ros::Time(1.0), ros1::depth_to_msg(cv::Mat(2, 2, CV_32FC1, cv::Scalar::all(1.0f)), "16UC1"));
  }
  named.rgb = "/cam/rgb";
  named.depth = "/cam/depth";
  const std::string no_info = error(named);
  EXPECT_NE(no_info.find("camera-info topic /camera/rgb/camera_info"), std::string::npos) << no_info;
  EXPECT_NE(no_info.find("the bag has no sensor_msgs/CameraInfo topic"), std::string::npos) << no_info;
  fs::remove_all(dir);
}

}  // namespace
}  // namespace s3m

namespace s3m {
namespace {

TEST(RosParams, SectionOverridesReplaceOnlyTheKeysTheyName) {
  const YAML::Node preset = YAML::Load("map: {resolution_m: 0.05, fusion: {policy: paper, k: 3}}\ncloud: {max_depth_m: 4.0}");
  const YAML::Node over = YAML::Load("map: {fusion: {k: 2}}\nflow: {integrate: keyframes}");
  const YAML::Node m = ros1::merge_yaml(preset, over);
  EXPECT_DOUBLE_EQ(m["map"]["resolution_m"].as<double>(), 0.05);
  EXPECT_EQ(m["map"]["fusion"]["policy"].as<std::string>(), "paper");
  EXPECT_EQ(m["map"]["fusion"]["k"].as<int>(), 2);
  EXPECT_DOUBLE_EQ(m["cloud"]["max_depth_m"].as<double>(), 4.0);
  EXPECT_EQ(m["flow"]["integrate"].as<std::string>(), "keyframes");
  EXPECT_EQ(preset["map"]["fusion"]["k"].as<int>(), 3);  // the inputs are not modified
  // The merged document goes through the preset parser: its checks still apply.
  const pipeline::PipelineConfig c = pipeline::pipeline_config_from_yaml(m, "(test)");
  EXPECT_EQ(c.map.fusion.k, 2);
  EXPECT_THROW(pipeline::pipeline_config_from_yaml(ros1::merge_yaml(m, YAML::Load("map: {no_such_key: 1}")), "(test)"),
               Error);
}

}  // namespace
}  // namespace s3m
