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
constexpr int kFrames = 50;

// What the test hears from the node.
struct Heard {
  std::mutex m;
  std::map<double, SE3> poses;  // stamp [s] -> T_map_c
  visualization_msgs::MarkerArray markers;
  sensor_msgs::PointCloud2 cloud;
  std::string query;
};

template <typename Pred>
bool wait_for(Pred pred, std::chrono::milliseconds timeout) {
  const auto until = std::chrono::steady_clock::now() + timeout;
  while (std::chrono::steady_clock::now() < until) {
    if (pred()) return true;
    std::this_thread::sleep_for(10ms);
  }
  return pred();
}

TEST(RosNode, TracksASimulatedFlightAndPublishesALabelledMap) {
  const fs::path dir = fs::temp_directory_path() / ("s3m_ros_node_" + std::to_string(::getpid()));
  fs::remove_all(dir);
  fs::create_directories(dir);
  const int port = rostest::free_port();
  rostest::use_private_ros_env(port, dir);
  rostest::Child master({S3M_ROSMASTER, "--core", "-p", std::to_string(port)}, dir / "master.log");
  int argc = 1;
  char name[] = "s3m_node_test";
  char* argv[] = {name, nullptr};
  ros::init(argc, argv, "s3m_node_test", ros::init_options::NoSigintHandler | ros::init_options::AnonymousName);
  ASSERT_TRUE(wait_for([] { return ros::master::check(); }, 30s)) << rostest::read_file(dir / "master.log");

  const std::string preset = std::string(S3M_SOURCE_DIR) + "/config/sim.yaml";
  rostest::Child node({S3M_NODE_BINARY, "__name:=s3m_node", "_config:=" + preset, "_use_labels:=true",
                       "_output_dir:=" + (dir / "out").string(), "_map_every_n_frames:=10",
                       "rgb/image:=/cam/rgb", "depth/image:=/cam/depth", "rgb/camera_info:=/cam/info",
                       "labels/image:=/cam/labels"},
                      dir / "node.log");
  const auto node_log = [&] { return rostest::read_file(dir / "node.log"); };

  ros::NodeHandle nh;
  ros::AsyncSpinner spinner(1);
  spinner.start();
  tf2_ros::Buffer tf_buffer;
  tf2_ros::TransformListener tf_listener(tf_buffer);
  Heard heard;
  auto pose_sub = nh.subscribe<geometry_msgs::PoseStamped>("/s3m_node/camera/pose", 100, [&](const geometry_msgs::PoseStamped::ConstPtr& m) {
    std::lock_guard l(heard.m);
    heard.poses[ros1::to_seconds(m->header.stamp)] = ros1::from_pose(m->pose);
  });
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
  auto rgb = nh.advertise<sensor_msgs::Image>("/cam/rgb", 5), depth = nh.advertise<sensor_msgs::Image>("/cam/depth", 5),
       labels = nh.advertise<sensor_msgs::Image>("/cam/labels", 5);
  auto info = nh.advertise<sensor_msgs::CameraInfo>("/cam/info", 5);
  auto query = nh.advertise<std_msgs::String>("/s3m_node/query", 1);
  ASSERT_TRUE(wait_for([&] {
    return rgb.getNumSubscribers() && depth.getNumSubscribers() && labels.getNumSubscribers() &&
           info.getNumSubscribers() && pose_sub.getNumPublishers() && query.getNumSubscribers();
  }, 60s)) << node_log();

  // Lock-step: publish frame i, wait for its pose (bounded), so a slow machine drops nothing.
  sim::SimConfig sc;
  sc.scene = "office";
  sc.seed = 7;
  sc.trajectory.type = "handheld";
  sc.trajectory.frames = kFrames;
  const sim::Simulation sim(sc);
  io::Trajectory gt;
  for (int i = 0; i < kFrames; ++i) {
    const RgbdFrame f = sim.frame(i);
    gt.push_back({f.t_s, sim.trajectory().samples[i].T_w_c});
    std_msgs::Header h;
    h.stamp = ros1::to_ros_time(f.t_s);
    h.frame_id = "camera_rgb_optical_frame";
    sensor_msgs::Image c = ros1::bgr_to_msg(f.rgb), d = ros1::depth_to_msg(f.depth_m, "16UC1"),
                       l = ros1::labels_to_msg(f.labels);
    sensor_msgs::CameraInfo ci = ros1::info_from_camera(sim.camera());
    c.header = d.header = l.header = ci.header = h;
    rgb.publish(c), depth.publish(d), labels.publish(l), info.publish(ci);
    wait_for([&] {
      std::lock_guard lk(heard.m);
      return heard.poses.count(ros1::to_seconds(h.stamp)) > 0;
    }, 20s);
  }

  // Poses against the ground truth.
  io::Trajectory est;
  {
    std::lock_guard l(heard.m);
    for (const auto& [t, T] : heard.poses) est.push_back({t, T});
  }
  EXPECT_GE(est.size(), static_cast<std::size_t>(kFrames - 2)) << node_log();
  ASSERT_GE(est.size(), 10u) << node_log();
  const eval::TrajectoryEvaluation ev = eval::evaluate_trajectory(gt, est, {}, "s3m_node");
  EXPECT_LT(ev.ate.stats_m.rmse, 0.05) << "ATE RMSE " << ev.ate.stats_m.rmse << " m";
  std::printf("s3m_node: %zu/%d poses, ATE RMSE %.4f m\n", est.size(), kFrames, ev.ate.stats_m.rmse);

  // TF map -> odom -> base_link -> camera (static, from the preset's T_c_r) composes to the
  // published camera pose: the chain and the calibration are consistent.
  {
    const double t_last = est.back().t_s;
    geometry_msgs::TransformStamped T;
    ASSERT_NO_THROW(T = tf_buffer.lookupTransform("map", "camera_rgb_optical_frame", ros1::to_ros_time(t_last),
                                                  ros::Duration(5.0)));
    const SE3 T_map_c_tf = ros1::from_transform(T.transform), T_map_c = est.back().T_w_x;
    EXPECT_LT((T_map_c_tf.translation() - T_map_c.translation()).norm(), 1e-6);
    EXPECT_LT((T_map_c_tf.linear() - T_map_c.linear()).norm(), 1e-6);
    // `map` is the robot body frame at the first tracked frame: base_link starts at the origin.
    const geometry_msgs::TransformStamped T0 =
        tf_buffer.lookupTransform("map", "base_link", ros1::to_ros_time(est.front().t_s), ros::Duration(1.0));
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
  spinner.stop();
  const int status = node.stop(60s);
  EXPECT_FALSE(node.killed()) << "s3m_node did not stop on SIGINT\n" << node_log();
  EXPECT_TRUE(WIFEXITED(status) && WEXITSTATUS(status) == 0) << node_log();
  master.stop(10s);
  ros::shutdown();
  fs::remove_all(dir);
}

}  // namespace
}  // namespace s3m
