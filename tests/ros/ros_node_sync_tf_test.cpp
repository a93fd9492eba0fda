// s3m_node's optional input paths, end to end like ros_node_test.cpp (private rosmaster on a
// free loopback port, the node as a child process, a simulated office flight published to it):
//  - ~approximate_sync: depth stamped 5 ms after colour (a driver without hardware sync; the frame
//    period is 33 ms). An ApproximateTime node and an ExactTime node hear the same stream: the
//    first processes every frame, the second none of the offset ones, and - the control that it is
//    connected and working - every frame of an aligned tail. With ~use_labels (the four-input
//    synchroniser) depth +5 ms and labels +3 ms: every frame is processed, and the node's ~labels
//    image of each frame (oracle segmenter, noise off) is exactly the label image sent with it.
//  - ~T_c_r_from_tf: the camera mount comes from a static TF base_link -> camera published here,
//    while the config holds a different (identity) slam.T_c_r: the node's robot poses must be its
//    camera poses times the TF's T_c_r, and the TF tree must agree with them.
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <iterator>
#include <map>
#include <memory>
#include <mutex>
#include <set>
#include <string>
#include <vector>

#include <geometry_msgs/PoseStamped.h>
#include <geometry_msgs/TransformStamped.h>
#include <gtest/gtest.h>
#include <nav_msgs/Odometry.h>
#include <ros/ros.h>
#include <sensor_msgs/Image.h>
#include <sensor_msgs/PointCloud2.h>
#include <sensor_msgs/point_cloud2_iterator.h>
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

  // s3m_node `name` on the sim preset with the segmenter off unless asked (poses are what most of
  // these tests check),
  // inputs remapped to the FramePublisher's /cam topics, plus `params` (_key:=value).
  static rostest::Child start_node(const std::string& name, const std::vector<std::string>& params,
                                   const std::string& segmenter = "none") {
    ros::param::set("/" + name + "/segmenter/type", segmenter);
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
std::set<double> stamps_of(const io::Trajectory& gt) {
  std::set<double> out;
  for (const auto& p : gt) out.insert(p.t_s);
  return out;
}

// The answers follow the ground truth as in the live test (se3-aligned ATE): the sets the node
// processed are the right ones (frame i's depth with frame i's colour). Returns the ATE RMSE [m].
double expect_tracks_ground_truth(const io::Trajectory& gt, const std::map<double, SE3>& poses,
                                  const std::string& name) {
  io::Trajectory est;
  for (const auto& [t, T] : poses) est.push_back({t, T});
  EXPECT_GE(est.size(), 10u);
  if (est.size() < 10u) return -1.0;
  const eval::TrajectoryEvaluation ev = eval::evaluate_trajectory(gt, est, {}, name);
  EXPECT_EQ(ev.matched, gt.size());
  EXPECT_LT(ev.ate.stats_m.rmse, 0.05) << "ATE RMSE " << ev.ate.stats_m.rmse << " m";
  return ev.ate.stats_m.rmse;
}

TEST_F(RosNodeInputs, ApproximateSyncPairsOffsetDepthWhereExactSyncPairsNothing) {
  ASSERT_TRUE(session_);
  constexpr int kOffsetFrames = 16, kAlignedFrames = 4, kFrames = kOffsetFrames + kAlignedFrames;
  rostest::StampOffsets offsets;
  offsets.depth_s = 0.005;  // < half the 33 ms frame period: the nearest depth is the frame's own
  rostest::Child approx = start_node("s3m_approx", {"_approximate_sync:=true"});
  rostest::Child exact = start_node("s3m_exact", {"_approximate_sync:=false"});
  ros::NodeHandle& nh = session_->nh();
  rostest::FramePublisher cam(nh, "/cam", /*labels=*/false);
  PoseRecorder<Odometry> approx_odom(nh, "/s3m_approx/camera/odom"), exact_odom(nh, "/s3m_exact/camera/odom");
  ASSERT_TRUE(wait_for([&] { return cam.connected(2) && approx_odom.connected() && exact_odom.connected(); }, 60s))
      << log("s3m_approx") << log("s3m_exact");

  // Lock-step (bounded waits): the approximate node answers offset frames one frame late (see
  // approx_answers_due), the exact node only the aligned tail, each at once.
  const io::Trajectory gt = rostest::fly_lockstep(
      cam, rostest::office_flight(kFrames), kFrames, kOffsetFrames, offsets,
      [&](int i) {
        const std::size_t exact_want = i < kOffsetFrames ? 0 : i - kOffsetFrames + 1;
        return approx_odom.count() >= rostest::approx_answers_due(i, kOffsetFrames) && exact_odom.count() >= exact_want;
      },
      [](int, const RgbdFrame&, const sensor_msgs::Image&) {});
  const std::set<double> all_stamps = stamps_of(gt), aligned_stamps = stamps_of(io::Trajectory(gt.begin() + kOffsetFrames, gt.end()));
  // Nothing is pending: each node answers in stamp order on one connection, so the answers to the
  // aligned tail (waited for above) come after any answer to an earlier frame.
  const std::map<double, SE3> approx_poses = approx_odom.poses(), exact_poses = exact_odom.poses();
  EXPECT_EQ(approx_odom.count(), static_cast<std::size_t>(kFrames)) << log("s3m_approx");
  EXPECT_EQ(keys(approx_poses), all_stamps);
  EXPECT_EQ(exact_odom.count(), static_cast<std::size_t>(kAlignedFrames)) << log("s3m_exact");
  EXPECT_EQ(keys(exact_poses), aligned_stamps);  // not one of the offset frames
  EXPECT_EQ(approx_odom.frames(), std::make_pair(std::string("map"), std::string("camera_rgb_optical_frame")));

  const double rmse = expect_tracks_ground_truth(gt, approx_poses, "s3m_approx");
  std::printf("approximate_sync: %zu/%d frames, ATE RMSE %.4f m; exact: %zu/%d (aligned only)\n",
              approx_poses.size(), kFrames, rmse, exact_poses.size(), kAlignedFrames);

  expect_clean_stop(approx, "s3m_approx");
  expect_clean_stop(exact, "s3m_exact");
}

// The node's ~labels images (stamp key -> class ids, row-major) and its last map/cloud.
class LabelsHeard {
 public:
  LabelsHeard(ros::NodeHandle& nh, const std::string& node)
      : labels_(nh.subscribe(node + "/labels", 50, &LabelsHeard::on_labels, this)),
        cloud_(nh.subscribe(node + "/map/cloud", 2, &LabelsHeard::on_cloud, this)) {}
  bool connected() const { return labels_.getNumPublishers() > 0 && cloud_.getNumPublishers() > 0; }
  std::map<double, std::vector<std::uint8_t>> images() const {
    std::lock_guard l(m_);
    return images_;
  }
  sensor_msgs::PointCloud2 cloud() const {
    std::lock_guard l(m_);
    return cloud_msg_;
  }

 private:
  void on_labels(const sensor_msgs::ImageConstPtr& m) {
    std::lock_guard l(m_);
    images_[ros1::to_seconds(m->header.stamp)] = m->encoding == "mono16" ? m->data : std::vector<std::uint8_t>{};
  }
  void on_cloud(const sensor_msgs::PointCloud2ConstPtr& m) {
    std::lock_guard l(m_);
    cloud_msg_ = *m;
  }
  mutable std::mutex m_;
  std::map<double, std::vector<std::uint8_t>> images_;
  sensor_msgs::PointCloud2 cloud_msg_;
  ros::Subscriber labels_, cloud_;  // last: unsubscribed before the rest goes
};

// The class ids on map/cloud's voxels.
std::set<std::uint16_t> cloud_labels(const sensor_msgs::PointCloud2& cloud) {
  std::set<std::uint16_t> out;
  if (cloud.width == 0) return out;
  for (sensor_msgs::PointCloud2ConstIterator<std::uint16_t> it(cloud, "label"); it != it.end(); ++it) out.insert(*it);
  return out;
}

// The four-input synchroniser (rgb, depth, camera_info, labels): depth +5 ms and labels +3 ms after
// colour. The oracle segmenter without noise passes the labels through, so the node's ~labels image
// of a frame is exactly the label image sent with that frame's colour when the sets pair right.
TEST_F(RosNodeInputs, ApproximateSyncPairsOffsetDepthAndLabelsWithTheirFrame) {
  ASSERT_TRUE(session_);
  constexpr int kOffsetFrames = 16, kAlignedFrames = 4, kFrames = kOffsetFrames + kAlignedFrames, kMapEvery = 5;
  rostest::StampOffsets offsets;
  offsets.depth_s = 0.005, offsets.labels_s = 0.003;  // both < half the 33 ms frame period
  const std::string name = "s3m_labels";
  ros::param::set("/" + name + "/segmenter/oracle/enabled", false);  // argmax = the labels sent
  ros::param::set("/" + name + "/flow/segment", std::string("all_frames"));
  rostest::Child node = start_node(name, {"_approximate_sync:=true", "_use_labels:=true", "labels/image:=/cam/labels",
                                          "_map_every_n_frames:=" + std::to_string(kMapEvery)}, "oracle");
  ros::NodeHandle& nh = session_->nh();
  rostest::FramePublisher cam(nh, "/cam", /*labels=*/true);
  PoseRecorder<Odometry> odom(nh, "/" + name + "/camera/odom");
  LabelsHeard heard(nh, "/" + name);
  ASSERT_TRUE(wait_for([&] { return cam.connected(1) && odom.connected() && heard.connected(); }, 60s)) << log(name);

  std::map<double, std::vector<std::uint8_t>> sent;  // colour stamp key -> the label image sent
  std::set<std::uint16_t> ids_sent;
  const io::Trajectory gt = rostest::fly_lockstep(
      cam, rostest::office_flight(kFrames), kFrames, kOffsetFrames, offsets,
      [&](int i) { return odom.count() >= rostest::approx_answers_due(i, kOffsetFrames); },
      [&](int, const RgbdFrame& f, const sensor_msgs::Image& l) {
        sent[stamp_key(f.t_s)] = l.data;
        for (auto it = f.labels.begin<std::uint16_t>(); it != f.labels.end<std::uint16_t>(); ++it)
          ids_sent.insert(*it);
      });
  EXPECT_EQ(odom.count(), static_cast<std::size_t>(kFrames)) << log(name);
  EXPECT_EQ(keys(odom.poses()), stamps_of(gt));  // with the count: one answer per frame
  const double rmse = expect_tracks_ground_truth(gt, odom.poses(), name);

  // Every frame's labels came back with its own colour stamp, pixel for pixel. The check tells
  // frames apart: the view moves, so consecutive label images differ.
  for (auto a = sent.begin(), b = std::next(a); b != sent.end(); ++a, ++b)
    ASSERT_NE(a->second, b->second) << "frames at " << a->first << " and " << b->first << " have the same labels";
  wait_for([&] { return heard.images().size() >= sent.size(); }, 10s);
  const auto images = heard.images();
  std::size_t same = 0;
  for (const auto& [t, data] : sent) {
    const auto it = images.find(t);
    if (it == images.end()) {
      ADD_FAILURE() << "no ~labels image for stamp " << t;
      continue;
    }
    EXPECT_TRUE(it->second == data) << "~labels image of stamp " << t << " is not the one sent with it";
    same += it->second == data;
  }
  EXPECT_EQ(images.size(), sent.size());

  // The labels reached the map: the map/cloud published after the last frame labels its voxels
  // with exactly the class ids sent (5 classes, each on >= 300 of the ~6 000 voxels; with the
  // segmenter off every label would be 0).
  ASSERT_TRUE(wait_for([&] {
    const sensor_msgs::PointCloud2 c = heard.cloud();
    return c.width > 0 && stamp_key(ros1::to_seconds(c.header.stamp)) == gt.back().t_s;
  }, 20s)) << log(name);
  const sensor_msgs::PointCloud2 cloud = heard.cloud();
  const std::set<std::uint16_t> ids_in_map = cloud_labels(cloud);
  EXPECT_EQ(ids_in_map, ids_sent);
  std::printf("approximate_sync + labels: %zu/%d poses (ATE RMSE %.4f m), %zu/%zu ~labels images equal to "
              "those sent, map/cloud %u voxels with %zu class ids (%zu sent)\n", odom.poses().size(), kFrames, rmse,
              same, sent.size(), cloud.width, ids_in_map.size(), ids_sent.size());
  expect_clean_stop(node, name);
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
