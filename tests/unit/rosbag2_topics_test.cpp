// Which driver wrote a recording, from topic names and types; the static transform tree.
#include <gtest/gtest.h>

#include "io_test_util.hpp"
#include "s3m/rosbag2/static_tf.hpp"
#include "s3m/rosbag2/topics.hpp"

namespace s3m::rosbag2 {
namespace {

using s3m::testing::expect_error;
const std::string kImage = "sensor_msgs/msg/Image", kInfo = "sensor_msgs/msg/CameraInfo",
                  kCompressed = "sensor_msgs/msg/CompressedImage";

TEST(Rosbag2Topics, RealsenseAlignedRawAndCompressed) {
  TopicTypes t = {{"/camera/camera/color/image_raw", kImage},
                  {"/camera/camera/color/camera_info", kInfo},
                  {"/camera/camera/aligned_depth_to_color/image_raw", kImage},
                  {"/camera/camera/depth/image_rect_raw", kImage},
                  {"/camera/camera/depth/camera_info", kInfo},
                  {"/tf_static", "tf2_msgs/msg/TFMessage"}};
  TopicSet s = choose_topics(t, "", "", "");
  EXPECT_EQ(s.recorder, "realsense2_camera");
  EXPECT_EQ(s.depth, "/camera/camera/aligned_depth_to_color/image_raw");
  EXPECT_TRUE(s.registered());
  EXPECT_TRUE(s.device_calibration);
  EXPECT_EQ(s.rgb_info, "/camera/camera/color/camera_info");

  t.erase("/camera/camera/aligned_depth_to_color/image_raw");
  t["/camera/camera/extrinsics/depth_to_color"] = "realsense2_camera_msgs/msg/Extrinsics";
  s = choose_topics(t, "", "", "");
  EXPECT_EQ(s.extrinsics, "/camera/camera/extrinsics/depth_to_color");
  EXPECT_EQ(s.depth, "/camera/camera/depth/image_rect_raw");
  EXPECT_EQ(s.depth_info, "/camera/camera/depth/camera_info");
  EXPECT_FALSE(s.registered());

  TopicTypes c = {{"/camera/color/image_raw/compressed", kCompressed},
                  {"/camera/color/camera_info", kInfo},
                  {"/camera/aligned_depth_to_color/image_raw/compressedDepth", kCompressed}};
  s = choose_topics(c, "", "", "");
  EXPECT_EQ(s.rgb, "/camera/color/image_raw/compressed");
  EXPECT_EQ(s.depth, "/camera/aligned_depth_to_color/image_raw/compressedDepth");
}

TEST(Rosbag2Topics, AzureKinectOrbbecAndTheSimulator) {
  EXPECT_EQ(
      choose_topics({{"/rgb/image_raw", kImage}, {"/depth_to_rgb/image_raw", kImage}}, "", "", "").recorder,
      "azure_kinect_ros_driver");
  const TopicSet o = choose_topics({{"/camera/color/image_raw", kImage},
                                    {"/camera/color/camera_info", kInfo},
                                    {"/camera/depth/image_raw", kImage},
                                    {"/camera/depth/camera_info", kInfo}},
                                   "", "", "");
  EXPECT_EQ(o.recorder, "orbbec_camera");
  EXPECT_TRUE(o.registered_if_same_info);
  const TopicSet sim = choose_topics(
      {{"/camera/rgb/image_color", kImage}, {"/camera/depth/image", kImage}, {"/camera/labels", kImage}}, "",
      "", "");
  EXPECT_EQ(sim.labels, "/camera/labels");
  EXPECT_TRUE(sim.registered());
}

TEST(Rosbag2Topics, NoneSeveralAndGivenTopics) {
  expect_error(
      [] {
        choose_topics({{"/left/image", kImage}}, "", "", "");
      },
      {"no camera driver", "/left/image (sensor_msgs/msg/Image)", "--rgb-topic"});
  const TopicTypes two = {{"/a/rgb/image_raw", kImage},
                          {"/a/depth_to_rgb/image_raw", kImage},
                          {"/b/rgb/image_raw", kImage},
                          {"/b/depth_to_rgb/image_raw", kImage}};
  expect_error([&] { choose_topics(two, "", "", ""); },
               {"several cameras", "/a/rgb/image_raw", "/b/rgb/image_raw"});
  const TopicSet b = choose_topics(two, "/b/rgb/image_raw", "/b/depth_to_rgb/image_raw", "");
  EXPECT_EQ(b.recorder, "azure_kinect_ros_driver, topics given");
  const TopicSet g = choose_topics({{"/x/image", kImage}, {"/x/camera_info", kInfo}, {"/y/depth", kImage}},
                                   "/x/image", "/y/depth", "");
  EXPECT_EQ(g.recorder, "topics given");
  EXPECT_EQ(g.rgb_info, "/x/camera_info");
}

TEST(Rosbag2StaticTf, LooksUpChainsBothWays) {
  StaticTf tf;
  TransformStamped a, b;
  a.header.frame_id = "base", a.child_frame_id = "cam",
  a.T_parent_child = make_se3(Vec3(1, 0, 0), Quat::Identity());
  b.header.frame_id = "cam", b.child_frame_id = "depth",
  b.T_parent_child = make_se3(Vec3(0, 0.05, 0), Quat::Identity());
  tf.add(a), tf.add(b);
  const auto T_base_depth = tf.lookup("base", "depth");
  ASSERT_TRUE(T_base_depth);
  EXPECT_TRUE(T_base_depth->translation().isApprox(Vec3(1, 0.05, 0)));
  const auto T_depth_base = tf.lookup("depth", "base");
  ASSERT_TRUE(T_depth_base);
  EXPECT_TRUE(T_depth_base->translation().isApprox(Vec3(-1, -0.05, 0)));
  EXPECT_FALSE(tf.lookup("base", "elsewhere"));
}

}  // namespace
}  // namespace s3m::rosbag2
