// s3m_node end to end, the acceptance test of issue #10: a private rosmaster on a free loopback
// port, s3m_node started as a child, a simulated flight (rendered here with s3m::sim) published as
// colour + depth + camera_info + labels; the node's camera poses must match the ground truth (ATE
// after se3 alignment) and its map topics must carry labelled voxels; ~save_map and ~query work;
// then everything is stopped (SIGINT, SIGKILL after a grace period) and reaped.
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <map>
#include <mutex>
#include <set>
#include <string>

#include <geometry_msgs/PoseStamped.h>
#include <gtest/gtest.h>
#include <nlohmann/json.hpp>
#include <ros/ros.h>
#include <sensor_msgs/PointCloud2.h>
#include <std_msgs/String.h>
#include <std_srvs/Trigger.h>
#include <tf2_ros/buffer.h>
#include <tf2_ros/transform_listener.h>
#include <visualization_msgs/MarkerArray.h>

#include "conversions.hpp"
#include "ros_test_util.hpp"
#include "s3m/eval/trajectory_eval.hpp"
#include "s3m/mapping/map_io.hpp"
#include "s3m/sim/simulate.hpp"

namespace s3m {
namespace {

namespace fs = std::filesystem;
using namespace std::chrono_literals;
using rostest::wait_for;
constexpr int kFrames = 50;

// The map and query topics the test hears from the node (poses: rostest::PoseRecorder).
struct Heard {
  std::mutex m;
  visualization_msgs::MarkerArray markers;
  sensor_msgs::PointCloud2 cloud;
  std::string query;
};

TEST(RosNode, TracksASimulatedFlightAndPublishesALabelledMap) {
  rostest::RosSession session("s3m_ros_node", S3M_ROSMASTER);
  const fs::path& dir = session.dir();
  const std::string preset = std::string(S3M_SOURCE_DIR) + "/config/sim.yaml";
  rostest::Child node({S3M_NODE_BINARY, "__name:=s3m_node", "_config:=" + preset, "_use_labels:=true",
                       "_output_dir:=" + (dir / "out").string(), "_map_every_n_frames:=10",
                       "rgb/image:=/cam/rgb", "depth/image:=/cam/depth", "rgb/camera_info:=/cam/info",
                       "labels/image:=/cam/labels"},
                      dir / "node.log");
  const auto node_log = [&] { return rostest::read_file(dir / "node.log"); };

  ros::NodeHandle& nh = session.nh();
  tf2_ros::Buffer tf_buffer;
  tf2_ros::TransformListener tf_listener(tf_buffer);
  Heard heard;
  rostest::PoseRecorder<geometry_msgs::PoseStamped> poses(nh, "/s3m_node/camera/pose");
  auto marker_sub = nh.subscribe<visualization_msgs::MarkerArray>("/s3m_node/map/markers", 2, [&](const visualization_msgs::MarkerArray::ConstPtr& m) {
    std::lock_guard l(heard.m);
    heard.markers = *m;
  });
  auto cloud_sub = nh.subscribe<sensor_msgs::PointCloud2>("/s3m_node/map/cloud", 2, [&](const sensor_msgs::PointCloud2::ConstPtr& m) {
    std::lock_guard l(heard.m);
    heard.cloud = *m;
  });
  auto query_sub = nh.subscribe<std_msgs::String>("/s3m_node/query_result", 2, [&](const std_msgs::String::ConstPtr& m) {
    std::lock_guard l(heard.m);
    heard.query = m->data;
  });
  rostest::FramePublisher cam(nh, "/cam", /*labels=*/true);
  auto query = nh.advertise<std_msgs::String>("/s3m_node/query", 1);
  ASSERT_TRUE(wait_for([&] { return cam.connected(1) && poses.connected() && query.getNumSubscribers(); }, 60s))
      << node_log();

  // Lock-step: publish frame i, wait for its pose (bounded), so a slow machine drops nothing.
  const sim::Simulation sim = rostest::office_flight(kFrames);
  io::Trajectory gt;
  std::map<double, ros::Time> sent;  // pose key (us) -> the exact stamp (ns), for TF lookups
  for (int i = 0; i < kFrames; ++i) {
    const RgbdFrame f = sim.frame(i);
    gt.push_back({f.t_s, sim.trajectory().samples[i].T_w_c});
    sent[rostest::stamp_key(f.t_s)] = ros1::to_ros_time(f.t_s);
    cam.publish(f, sim.camera());
    wait_for([&] { return poses.has(rostest::stamp_key(f.t_s)); }, 20s);
  }

  // Poses against the ground truth.
  io::Trajectory est;
  for (const auto& [t, T] : poses.poses()) est.push_back({t, T});
  EXPECT_GE(est.size(), static_cast<std::size_t>(kFrames - 2)) << node_log();
  ASSERT_GE(est.size(), 10u) << node_log();
  const eval::TrajectoryEvaluation ev = eval::evaluate_trajectory(gt, est, {}, "s3m_node");
  EXPECT_LT(ev.ate.stats_m.rmse, 0.05) << "ATE RMSE " << ev.ate.stats_m.rmse << " m";
  std::printf("s3m_node: %zu/%d poses, ATE RMSE %.4f m\n", est.size(), kFrames, ev.ate.stats_m.rmse);

  // TF map -> odom -> base_link -> camera (static, from the preset's T_c_r) composes to the
  // published camera pose: the chain and the calibration are consistent.
  {
    // At the exact stamp: the microsecond key, when rounded up, would ask TF to extrapolate.
    const ros::Time t_last = sent.at(est.back().t_s);
    geometry_msgs::TransformStamped T;
    ASSERT_NO_THROW(T = tf_buffer.lookupTransform("map", "camera_rgb_optical_frame", t_last,
                                                  ros::Duration(5.0)));
    const SE3 T_map_c_tf = ros1::from_transform(T.transform), T_map_c = est.back().T_w_x;
    EXPECT_LT((T_map_c_tf.translation() - T_map_c.translation()).norm(), 1e-6);
    EXPECT_LT((T_map_c_tf.linear() - T_map_c.linear()).norm(), 1e-6);
    // `map` is the robot body frame at the first tracked frame: base_link starts at the origin.
    const geometry_msgs::TransformStamped T0 =
        tf_buffer.lookupTransform("map", "base_link", sent.at(est.front().t_s), ros::Duration(1.0));
    EXPECT_LT(ros1::from_transform(T0.transform).translation().norm(), 1e-9);
  }

  // The map topics: class-coloured voxels of several classes, and a cloud with the label field.
  ASSERT_TRUE(wait_for([&] {
    std::lock_guard l(heard.m);
    return heard.markers.markers.size() > 1 && heard.cloud.width > 0;
  }, 20s)) << node_log();
  {
    std::lock_guard l(heard.m);
    std::set<std::string> classes;
    std::size_t voxels = 0;
    for (const auto& m : heard.markers.markers)
      if (m.action == visualization_msgs::Marker::ADD && m.ns != "unknown" && !m.points.empty()) {
        classes.insert(m.ns);
        voxels += m.points.size();
      }
    EXPECT_GE(classes.size(), 3u);  // an office: at least wall, floor and one piece of furniture
    EXPECT_TRUE(classes.count("floor") && classes.count("wall"));
    EXPECT_GT(voxels, 500u);
    std::printf("s3m_node: map/markers %zu labelled voxels in %zu classes, map/cloud %u points\n", voxels,
                classes.size(), heard.cloud.width);
    std::set<std::string> fields;
    for (const auto& f : heard.cloud.fields) fields.insert(f.name);
    EXPECT_EQ(fields, (std::set<std::string>{"x", "y", "z", "rgb", "label", "confidence"}));
    EXPECT_EQ(heard.cloud.header.frame_id, "map");
  }

  // Query by class, and saving the map.
  std_msgs::String floor;
  floor.data = "floor";
  query.publish(floor);
  ASSERT_TRUE(wait_for([&] {
    std::lock_guard l(heard.m);
    return !heard.query.empty();
  }, 20s));
  {
    std::lock_guard l(heard.m);
    const auto q = nlohmann::json::parse(heard.query);
    ASSERT_TRUE(q.contains("instances")) << heard.query;
    EXPECT_GE(q["instances"].size(), 1u) << heard.query;
  }
  std_srvs::Trigger save;
  ASSERT_TRUE(ros::service::call("/s3m_node/save_map", save)) << node_log();
  EXPECT_TRUE(save.response.success) << save.response.message;
  const auto tree = mapping::load_semantic_map((dir / "out" / "map.ot").string());
  EXPECT_GT(tree->getNumLeafNodes(), 500u);

  // Shut down: the node finishes (final map rebuild, save) on SIGINT within the grace period.
  const int status = node.stop(60s);
  EXPECT_FALSE(node.killed()) << "s3m_node did not stop on SIGINT\n" << node_log();
  EXPECT_TRUE(WIFEXITED(status) && WEXITSTATUS(status) == 0) << node_log();
}

}  // namespace
}  // namespace s3m
