// s3m_node and saved sessions (issue 23): a node maps a simulated flight and ~save_map writes the
// SLAM session too (slam_map.bin, kept_clouds.bin); a second node started with ~map on that folder
// relocalises at its very first frame and publishes its poses in the first node's `map` frame;
// its own ~save_map writes the extended session. A ~map folder without a SLAM map stops the node
// at start with a message naming it.
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <string>

#include <geometry_msgs/PoseStamped.h>
#include <gtest/gtest.h>
#include <ros/ros.h>
#include <std_srvs/Trigger.h>

#include "conversions.hpp"
#include "ros_test_util.hpp"
#include "s3m/sim/simulate.hpp"

namespace s3m {
namespace {

namespace fs = std::filesystem;
using namespace std::chrono_literals;
using rostest::wait_for;
constexpr int kFrames = 40;
constexpr int kSecondFrom = 20;  // the second node flies the second half again

std::vector<std::string> node_args(const std::string& out, const std::vector<std::string>& extra = {}) {
  std::vector<std::string> a{S3M_NODE_BINARY, "__name:=s3m_node", "_config:=" + std::string(S3M_SOURCE_DIR) + "/config/sim.yaml",
                             "_use_labels:=true", "_output_dir:=" + out, "_save_on_exit:=false",
                             "rgb/image:=/cam/rgb", "depth/image:=/cam/depth", "rgb/camera_info:=/cam/info",
                             "labels/image:=/cam/labels"};
  a.insert(a.end(), extra.begin(), extra.end());
  return a;
}

// Publishes frames [from, to) of the flight lock-step (each waits for its pose, bounded).
void fly(rostest::FramePublisher& cam, const sim::Simulation& sim, int from, int to,
         const rostest::PoseRecorder<geometry_msgs::PoseStamped>& poses) {
  for (int i = from; i < to; ++i) {
    const RgbdFrame f = sim.frame(i);
    cam.publish(f, sim.camera());
    wait_for([&] { return poses.has(rostest::stamp_key(f.t_s)); }, 20s);
  }
}

bool call_save() {
  std_srvs::Trigger save;
  return ros::service::call("/s3m_node/save_map", save) && save.response.success;
}

TEST(RosNodeMap, SecondNodeContinuesInTheSavedSession) {
  rostest::RosSession session("s3m_ros_node_map", S3M_ROSMASTER);
  const fs::path& dir = session.dir();
  ros::NodeHandle& nh = session.nh();
  const sim::Simulation sim = rostest::office_flight(kFrames);
  rostest::FramePublisher cam(nh, "/cam", /*labels=*/true);

  // 1. The first node maps the flight; ~save_map writes the SLAM session with the map.
  std::map<double, SE3> first;
  {
    rostest::PoseRecorder<geometry_msgs::PoseStamped> poses(nh, "/s3m_node/camera/pose");
    rostest::Child node(node_args((dir / "run1").string()), dir / "node1.log");
    ASSERT_TRUE(wait_for([&] { return cam.connected(1) && poses.connected(); }, 60s)) << rostest::read_file(dir / "node1.log");
    fly(cam, sim, 0, kFrames, poses);
    ASSERT_TRUE(call_save()) << rostest::read_file(dir / "node1.log");
    first = poses.poses();
    node.stop(60s);
  }
  for (const char* f : {"slam_map.bin", "kept_clouds.bin", "map.ot"}) EXPECT_TRUE(fs::exists(dir / "run1" / f)) << f;
  ASSERT_GE(first.size(), std::size_t(kFrames - 2));

  // 2. The second node continues in it: a pose for its first frame, in the first node's `map`.
  rostest::PoseRecorder<geometry_msgs::PoseStamped> poses(nh, "/s3m_node/camera/pose");
  rostest::Child node(node_args((dir / "run2").string(), {"_map:=" + (dir / "run1").string()}), dir / "node2.log");
  const auto log = [&] { return rostest::read_file(dir / "node2.log"); };
  ASSERT_TRUE(wait_for([&] { return cam.connected(1) && poses.connected(); }, 60s)) << log();
  fly(cam, sim, kSecondFrom, kFrames, poses);
  const std::map<double, SE3> second = poses.poses();
  EXPECT_TRUE(second.count(rostest::stamp_key(sim.frame(kSecondFrom).t_s))) << "relocalised at the first frame\n" << log();
  EXPECT_GE(second.size(), std::size_t(kFrames - kSecondFrom - 1)) << log();
  double worst = 0;
  for (const auto& [t, T] : second)
    if (first.count(t)) worst = std::max(worst, (T.translation() - first.at(t).translation()).norm());
  std::printf("s3m_node with ~map: %zu poses, worst distance to the first node's pose of the frame %.4f m\n",
              second.size(), worst);
  std::fflush(stdout);  // before the next fork (the child would print the buffer again)
  EXPECT_LT(worst, 0.03) << "one map frame for both sessions";
  ASSERT_TRUE(call_save()) << log();
  EXPECT_TRUE(fs::exists(dir / "run2" / "slam_map.bin"));
  EXPECT_TRUE(fs::exists(dir / "run2" / "kept_clouds.bin"));
  node.stop(60s);
  EXPECT_FALSE(node.killed()) << log();
  // Read once the node has exited: its stdout goes to a file, block-buffered until then.
  EXPECT_NE(log().find("continuing in"), std::string::npos) << log();

  // 3. A ~map folder without a SLAM map stops the node before any frame.
  rostest::Child bad(node_args((dir / "run3").string(), {"_map:=" + (dir / "nothing_here").string()}), dir / "node3.log");
  EXPECT_TRUE(wait_for([&] { return !bad.running(); }, 30s));
  EXPECT_NE(rostest::read_file(dir / "node3.log").find("nothing_here' holds no slam_map.bin"), std::string::npos)
      << rostest::read_file(dir / "node3.log");
}

}  // namespace
}  // namespace s3m
