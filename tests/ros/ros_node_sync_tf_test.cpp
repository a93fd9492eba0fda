// s3m_node's two optional input paths, end to end like ros_node_test.cpp (private rosmaster on a
// free loopback port, the node as a child process, a simulated office flight published to it):
//  - ~approximate_sync: depth stamped 5 ms after colour (a driver without hardware sync; the frame
//    period is 33 ms). An ApproximateTime node and an ExactTime node hear the same stream: the
//    first processes every frame, the second none of the offset ones, and - the control that it is
//    connected and working - every frame of an aligned tail.
//  - ~T_c_r_from_tf: the camera mount comes from a static TF base_link -> camera published here,
//    while the config holds a different (identity) slam.T_c_r: the node's robot poses must be its
//    camera poses times the TF's T_c_r, and the TF tree must agree with them.
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <map>
#include <memory>
#include <set>
#include <string>
#include <vector>

#include <geometry_msgs/PoseStamped.h>
#include <geometry_msgs/TransformStamped.h>
#include <gtest/gtest.h>
#include <nav_msgs/Odometry.h>
#include <ros/ros.h>
#include <tf2_ros/buffer.h>
#include <tf2_ros/static_transform_broadcaster.h>
#include <tf2_ros/transform_listener.h>
#include <xmlrpcpp/XmlRpcValue.h>

#include "conversions.hpp"
#include "ros_test_util.hpp"
#include "s3m/eval/trajectory_eval.hpp"
#include "s3m/sim/simulate.hpp"

namespace s3m {
namespace {

namespace fs = std::filesystem;
using namespace std::chrono_literals;
using rostest::PoseRecorder;
using rostest::stamp_key;
using rostest::wait_for;
using Odometry = nav_msgs::Odometry;
using PoseStamped = geometry_msgs::PoseStamped;

double angle_rad(const SE3& a, const SE3& b) {
  return Eigen::AngleAxisd(a.linear().transpose() * b.linear()).angle();
}
double dist_m(const SE3& a, const SE3& b) { return (a.translation() - b.translation()).norm(); }

// One ROS session (master + this process as a node) for the suite: roscpp initialises once.
class RosNodeInputs : public ::testing::Test {
 protected:
  static void SetUpTestSuite() { session_ = std::make_unique<rostest::RosSession>("s3m_ros_inputs", S3M_ROSMASTER); }
  static void TearDownTestSuite() { session_.reset(); }

  // s3m_node `name` on the sim preset with the segmenter off (poses are what these tests check),
  // inputs remapped to the FramePublisher's /cam topics, plus `params` (_key:=value).
  static rostest::Child start_node(const std::string& name, const std::vector<std::string>& params) {
    ros::param::set("/" + name + "/segmenter/type", std::string("none"));
    std::vector<std::string> argv = {S3M_NODE_BINARY, "__name:=" + name,
                                     "_config:=" + std::string(S3M_SOURCE_DIR) + "/config/sim.yaml",
                                     "_save_on_exit:=false", "_map_every_n_frames:=1000",
                                     "rgb/image:=/cam/rgb", "depth/image:=/cam/depth", "rgb/camera_info:=/cam/info"};
    argv.insert(argv.end(), params.begin(), params.end());
    return rostest::Child(argv, log_path(name));
  }
  static fs::path log_path(const std::string& name) { return session_->dir() / (name + ".log"); }
  static std::string log(const std::string& name) { return rostest::read_file(log_path(name)); }

  // SIGINT; the node must exit 0 within the grace period.
  static void expect_clean_stop(rostest::Child& node, const std::string& name) {
    const int status = node.stop(60s);
    EXPECT_FALSE(node.killed()) << name << " did not stop on SIGINT\n" << log(name);
    EXPECT_TRUE(WIFEXITED(status) && WEXITSTATUS(status) == 0) << log(name);
  }

  static std::unique_ptr<rostest::RosSession> session_;
};
std::unique_ptr<rostest::RosSession> RosNodeInputs::session_;

std::set<double> keys(const std::map<double, SE3>& poses) {
  std::set<double> out;
  for (const auto& kv : poses) out.insert(kv.first);
  return out;
}

TEST_F(RosNodeInputs, ApproximateSyncPairsOffsetDepthWhereExactSyncPairsNothing) {
  ASSERT_TRUE(session_);
  constexpr int kOffsetFrames = 16, kAlignedFrames = 4, kFrames = kOffsetFrames + kAlignedFrames;
  constexpr double kDepthOffsetS = 0.005;  // < half the 33 ms frame period: the nearest depth is the frame's own
  rostest::Child approx = start_node("s3m_approx", {"_approximate_sync:=true"});
  rostest::Child exact = start_node("s3m_exact", {"_approximate_sync:=false"});
  ros::NodeHandle& nh = session_->nh();
  rostest::FramePublisher cam(nh, "/cam", /*labels=*/false);
  PoseRecorder<Odometry> approx_odom(nh, "/s3m_approx/camera/odom"), exact_odom(nh, "/s3m_exact/camera/odom");
  ASSERT_TRUE(wait_for([&] { return cam.connected(2) && approx_odom.connected() && exact_odom.connected(); }, 60s))
      << log("s3m_approx") << log("s3m_exact");

  const sim::Simulation sim = rostest::office_flight(kFrames);
  std::set<double> all_stamps, aligned_stamps;
  io::Trajectory gt;
  bool behind = false;  // a wait timed out: the counts below fail; do not wait 20 s per frame for that
  for (int i = 0; i < kFrames; ++i) {
    const RgbdFrame f = sim.frame(i);
    const bool offset = i < kOffsetFrames;
    gt.push_back({stamp_key(f.t_s), sim.trajectory().samples[i].T_w_c});
    all_stamps.insert(stamp_key(f.t_s));
    if (!offset) aligned_stamps.insert(stamp_key(f.t_s));
    cam.publish(f, sim.camera(), offset ? kDepthOffsetS : 0.0);
    // Lock-step (bounded waits). ApproximateTime emits a set once a later message proves it the best
    // one, so while depth is offset the approximate node answers frame i when frame i+1 arrives
    // (the first aligned frame flushes the last offset one); aligned frames are answered at once.
    const std::size_t approx_want = offset ? i : i + 1;
    const std::size_t exact_want = offset ? 0 : i - kOffsetFrames + 1;
    const bool answered = wait_for([&] {
      return approx_odom.count() >= approx_want && exact_odom.count() >= exact_want;
    }, behind ? 500ms : 20s);
    behind = behind || !answered;
  }
  // Nothing is pending: each node answers in stamp order on one connection, so the answers to the
  // aligned tail (waited for above) come after any answer to an earlier frame.
  const std::map<double, SE3> approx_poses = approx_odom.poses(), exact_poses = exact_odom.poses();
  EXPECT_EQ(approx_odom.count(), static_cast<std::size_t>(kFrames)) << log("s3m_approx");
  EXPECT_EQ(keys(approx_poses), all_stamps);
  EXPECT_EQ(exact_odom.count(), static_cast<std::size_t>(kAlignedFrames)) << log("s3m_exact");
  EXPECT_EQ(keys(exact_poses), aligned_stamps);  // not one of the offset frames
  EXPECT_EQ(approx_odom.frames(), std::make_pair(std::string("map"), std::string("camera_rgb_optical_frame")));

  // The approximate pairs are the right ones (frame i's depth with frame i's colour): the poses
  // follow the ground truth as in the live test.
  io::Trajectory est;
  for (const auto& [t, T] : approx_poses) est.push_back({t, T});
  ASSERT_GE(est.size(), 10u);
  const eval::TrajectoryEvaluation ev = eval::evaluate_trajectory(gt, est, {}, "s3m_approx");
  EXPECT_EQ(ev.matched, static_cast<std::size_t>(kFrames));
  EXPECT_LT(ev.ate.stats_m.rmse, 0.05) << "ATE RMSE " << ev.ate.stats_m.rmse << " m";
  std::printf("approximate_sync: %zu/%d frames, ATE RMSE %.4f m; exact: %zu/%d (aligned only)\n", est.size(),
              kFrames, ev.ate.stats_m.rmse, exact_poses.size(), kAlignedFrames);

  expect_clean_stop(approx, "s3m_approx");
  expect_clean_stop(exact, "s3m_exact");
}

// base_link -> camera: the camera 0.12 m forward, 0.04 m right and 0.25 m up, looking forward
// (optical z = body x, optical x = -body y, optical y = -body z), yawed 20 deg left and pitched
// 15 deg down. Far from the identity that the config holds.
SE3 camera_mount_T_r_c() {
  Mat3 R_r_optical;
  R_r_optical << 0, 0, 1, -1, 0, 0, 0, -1, 0;
  const double deg = M_PI / 180.0;
  const Mat3 R = (Eigen::AngleAxisd(20 * deg, Vec3::UnitZ()) * Eigen::AngleAxisd(15 * deg, Vec3::UnitY()))
                     .toRotationMatrix() * R_r_optical;
  return make_se3(R, Vec3(0.12, -0.04, 0.25));
}

XmlRpc::XmlRpcValue identity_pose_param() {
  XmlRpc::XmlRpcValue p;
  for (int i = 0; i < 3; ++i) p["t"][i] = 0.0;
  for (int i = 0; i < 4; ++i) p["q"][i] = i == 3 ? 1.0 : 0.0;
  return p;
}

TEST_F(RosNodeInputs, CameraMountFromTfReplacesTheConfigsTcr) {
  ASSERT_TRUE(session_);
  constexpr int kFrames = 15;
  const std::string frame = "camera_rgb_optical_frame";
  const SE3 T_r_c = camera_mount_T_r_c(), T_c_r = T_r_c.inverse();
  ASSERT_GT(T_c_r.translation().norm(), 0.2);  // using the config's identity instead fails every check below
  tf2_ros::StaticTransformBroadcaster static_tf;
  geometry_msgs::TransformStamped mount;
  mount.header.stamp = ros::Time::now();
  mount.header.frame_id = "base_link";
  mount.child_frame_id = frame;
  mount.transform = ros1::to_transform(T_r_c);
  static_tf.sendTransform(mount);
  ros::param::set("/s3m_tf/slam/T_c_r", identity_pose_param());
  rostest::Child node = start_node("s3m_tf", {"_T_c_r_from_tf:=true"});

  ros::NodeHandle& nh = session_->nh();
  tf2_ros::Buffer tf_buffer;
  tf2_ros::TransformListener tf_listener(tf_buffer);
  rostest::FramePublisher cam(nh, "/cam", /*labels=*/false);
  PoseRecorder<PoseStamped> cam_pose(nh, "/s3m_tf/camera/pose"), robot_pose(nh, "/s3m_tf/robot/pose");
  PoseRecorder<Odometry> robot_odom(nh, "/s3m_tf/robot/odom");
  ASSERT_TRUE(wait_for([&] {
    return cam.connected(1) && cam_pose.connected() && robot_pose.connected() && robot_odom.connected();
  }, 60s)) << log("s3m_tf");

  const sim::Simulation sim = rostest::office_flight(kFrames);
  std::vector<double> stamps;  // the recorders' keys (us)
  ros::Time t_last;            // the exact stamp (ns) for TF lookups: a key rounded up would extrapolate
  bool behind = false;         // a wait timed out (the counts below fail): wait briefly from then on
  for (int i = 0; i < kFrames; ++i) {
    const RgbdFrame f = sim.frame(i);
    stamps.push_back(stamp_key(f.t_s));
    t_last = ros1::to_ros_time(f.t_s);
    cam.publish(f, sim.camera());
    const bool answered = wait_for([&] { return robot_odom.has(stamps.back()) && robot_pose.has(stamps.back()); },
                                   behind ? 500ms : 20s);
    behind = behind || !answered;
  }
  const auto T_map_c = cam_pose.poses(), T_map_r = robot_pose.poses(), T_map_r_odom = robot_odom.poses();
  ASSERT_EQ(robot_odom.count(), static_cast<std::size_t>(kFrames)) << log("s3m_tf");
  ASSERT_EQ(keys(T_map_c), std::set<double>(stamps.begin(), stamps.end()));
  ASSERT_EQ(keys(T_map_r), keys(T_map_c));
  EXPECT_EQ(robot_odom.frames(), std::make_pair(std::string("map"), std::string("base_link")));

  // T_map_r = T_map_c * T_c_r with the TF's T_c_r, for the node's own poses of each stamp; `map`
  // is the robot frame at the first frame; the robot moves as the ground-truth robot (the camera's
  // ground truth carried through the same mount), which a wrong T_c_r would rotate.
  const SE3 T_r0_w_gt = (sim.trajectory().samples[0].T_w_c * T_c_r).inverse();
  double worst_gt_m = 0;
  for (int i = 0; i < kFrames; ++i) {
    const double t = stamps[i];
    const SE3 expect = T_map_c.at(t) * T_c_r;
    EXPECT_LT(dist_m(T_map_r.at(t), expect), 1e-6) << "frame " << i;
    EXPECT_LT(angle_rad(T_map_r.at(t), expect), 1e-6) << "frame " << i;
    EXPECT_LT(dist_m(T_map_r_odom.at(t), T_map_r.at(t)), 1e-9);
    EXPECT_LT(angle_rad(T_map_r_odom.at(t), T_map_r.at(t)), 1e-9);
    const SE3 T_map_r_gt = T_r0_w_gt * sim.trajectory().samples[i].T_w_c * T_c_r;
    worst_gt_m = std::max(worst_gt_m, dist_m(T_map_r.at(t), T_map_r_gt));
  }
  EXPECT_LT(dist_m(T_map_r.at(stamps[0]), SE3::Identity()), 1e-9);
  EXPECT_LT(angle_rad(T_map_r.at(stamps[0]), SE3::Identity()), 1e-9);
  EXPECT_LT(worst_gt_m, 0.05);
  std::printf("T_c_r_from_tf: %d/%d robot poses = camera pose * TF T_c_r; worst robot position vs ground "
              "truth %.4f m\n", static_cast<int>(T_map_r.size()), kFrames, worst_gt_m);

  // The TF tree map -> odom -> base_link -> camera (the last link is ours) at the last stamp.
  const auto lookup = [&](const std::string& parent, const std::string& child) {
    return ros1::from_transform(tf_buffer.lookupTransform(parent, child, t_last, ros::Duration(5.0)).transform);
  };
  SE3 T_map_odom, T_odom_base, T_map_cam_tf;
  ASSERT_NO_THROW(T_map_odom = lookup("map", "odom"));
  ASSERT_NO_THROW(T_odom_base = lookup("odom", "base_link"));
  ASSERT_NO_THROW(T_map_cam_tf = lookup("map", frame));
  EXPECT_LT(dist_m(T_map_odom, SE3::Identity()) + angle_rad(T_map_odom, SE3::Identity()), 1e-9);
  EXPECT_LT(dist_m(T_odom_base, T_map_r.at(stamps.back())), 1e-6);
  EXPECT_LT(angle_rad(T_odom_base, T_map_r.at(stamps.back())), 1e-6);
  EXPECT_LT(dist_m(T_map_cam_tf, T_map_c.at(stamps.back())), 1e-6);
  EXPECT_LT(angle_rad(T_map_cam_tf, T_map_c.at(stamps.back())), 1e-6);

  expect_clean_stop(node, "s3m_tf");
}

}  // namespace
}  // namespace s3m
