// s3m_node with a depth stream that is not registered to colour, as realsense2_camera publishes it
// without align_depth: depth/image_rect_raw (848x480, its own optical frame), depth/camera_info and
// the driver's static TF between the two optical frames. Same set-up as ros_node_test.cpp (private
// rosmaster on a free loopback port, nodes as child processes, a simulated office flight; its
// depth is drawn into a depth camera 1.5 cm beside the colour camera before it is published).
//  - ~align_depth:=true: the node places the depth camera with depth/camera_info and TF, draws the
//    depth into the colour camera (io::DepthToColour) and tracks the flight's ground truth.
//  - without it: the node stops at the first frame, saying the depth is not registered and how to
//    fix it (exit 1), instead of running on depth of the wrong size.
#include <sys/wait.h>

#include <chrono>
#include <cstdio>
#include <filesystem>
#include <string>
#include <vector>

#include <geometry_msgs/PoseStamped.h>
#include <geometry_msgs/TransformStamped.h>
#include <gtest/gtest.h>
#include <ros/ros.h>
#include <sensor_msgs/CameraInfo.h>
#include <sensor_msgs/Image.h>
#include <tf2_ros/static_transform_broadcaster.h>

#include "conversions.hpp"
#include "ros_test_util.hpp"
#include "s3m/eval/trajectory_eval.hpp"
#include "s3m/io/depth_to_colour.hpp"
#include "s3m/sim/simulate.hpp"

namespace s3m {
namespace {

namespace fs = std::filesystem;
using namespace std::chrono_literals;
using rostest::PoseRecorder;
using rostest::stamp_key;
using rostest::wait_for;
using PoseStamped = geometry_msgs::PoseStamped;

const std::string kColourFrame = "camera_color_optical_frame", kDepthFrame = "camera_depth_optical_frame";

PinholeCamera d4xx_depth_camera() {
  PinholeCamera d;
  d.fx = d.fy = 425, d.cx = 423.5, d.cy = 239.5;
  d.width = 848, d.height = 480;
  d.depth_factor = 1000;
  return d;
}

const SE3 kT_c_d = make_se3(Vec3(-0.015, 0.0003, 0.0002), Quat(Eigen::AngleAxisd(0.006, Vec3(0.3, 1, 0.2).normalized())));

// realsense2_camera's topics and frames: colour and raw depth, each with its CameraInfo.
class RealsensePublisher {
 public:
  explicit RealsensePublisher(ros::NodeHandle& nh)
      : rgb_(nh.advertise<sensor_msgs::Image>("/rs/color/image_raw", 5)),
        rgb_info_(nh.advertise<sensor_msgs::CameraInfo>("/rs/color/camera_info", 5)),
        depth_(nh.advertise<sensor_msgs::Image>("/rs/depth/image_rect_raw", 5)),
        // Latched, and sent once before the first frame: the aligned node then has it when the
        // first frame comes (it skips frames until it has; a driver sends it with every image).
        depth_info_(nh.advertise<sensor_msgs::CameraInfo>("/rs/depth/camera_info", 5, /*latch=*/true)) {}
  // n nodes hear colour and depth; one (the aligned node) hears depth/camera_info.
  bool connected(unsigned n) const {
    return rgb_.getNumSubscribers() >= n && rgb_info_.getNumSubscribers() >= n && depth_.getNumSubscribers() >= n &&
           depth_info_.getNumSubscribers() >= 1;
  }
  void publish_depth_info() { depth_info_.publish(depth_info()); }
  void publish(const RgbdFrame& f, const PinholeCamera& colour, const io::DepthToColour& to_depth_camera) {
    std_msgs::Header h;
    h.stamp = ros1::to_ros_time(f.t_s);
    h.frame_id = kColourFrame;
    sensor_msgs::Image c = ros1::bgr_to_msg(f.rgb), d = ros1::depth_to_msg(to_depth_camera(f.depth_m), "16UC1");
    sensor_msgs::CameraInfo ci = ros1::info_from_camera(colour), di = depth_info();
    c.header = ci.header = d.header = di.header = h;
    d.header.frame_id = di.header.frame_id = kDepthFrame;
    ci.P[3] = 0;  // a driver's CameraInfo carries no virtual stereo term
    depth_info_.publish(di), rgb_.publish(c), rgb_info_.publish(ci), depth_.publish(d);
  }

 private:
  static sensor_msgs::CameraInfo depth_info() {
    sensor_msgs::CameraInfo di = ros1::info_from_camera(d4xx_depth_camera());
    di.header.frame_id = kDepthFrame;
    di.P[3] = 0;
    return di;
  }
  ros::Publisher rgb_, rgb_info_, depth_, depth_info_;
};

// The driver's static frames: both optical frames hang off camera_link.
void publish_static_frames(tf2_ros::StaticTransformBroadcaster& tf) {
  const SE3 T_link_c = make_se3(Vec3(0, 0.015, 0), Quat(0.5, -0.5, 0.5, -0.5));
  std::vector<geometry_msgs::TransformStamped> frames;
  for (const auto& [child, T] : {std::pair{kColourFrame, T_link_c}, std::pair{kDepthFrame, SE3(T_link_c * kT_c_d)}}) {
    geometry_msgs::TransformStamped ts;
    ts.header.stamp = ros::Time::now(), ts.header.frame_id = "camera_link", ts.child_frame_id = child;
    ts.transform = ros1::to_transform(T);
    frames.push_back(ts);
  }
  tf.sendTransform(frames);
}

rostest::Child start_node(const rostest::RosSession& session, const std::string& name, bool align) {
  ros::param::set("/" + name + "/segmenter/type", std::string("none"));
  // sim.yaml states its depth registered; as a live camera's preset would, this one asks.
  ros::param::set("/" + name + "/dataset/depth_registration", std::string("auto"));
  std::vector<std::string> argv = {S3M_NODE_BINARY, "__name:=" + name,
                                   "_config:=" + std::string(S3M_SOURCE_DIR) + "/config/sim.yaml",
                                   "_save_on_exit:=false", "_map_every_n_frames:=1000",
                                   "rgb/image:=/rs/color/image_raw", "rgb/camera_info:=/rs/color/camera_info",
                                   "depth/image:=/rs/depth/image_rect_raw", "depth/camera_info:=/rs/depth/camera_info"};
  if (align) argv.push_back("_align_depth:=true");
  return rostest::Child(argv, session.dir() / (name + ".log"));
}

TEST(RosNodeRawDepth, AlignDepthTracksRawRealsenseDepthAndWithoutItTheNodeSaysWhy) {
  rostest::RosSession session("s3m_ros_raw_depth", S3M_ROSMASTER);
  const auto log = [&](const std::string& name) { return rostest::read_file(session.dir() / (name + ".log")); };
  tf2_ros::StaticTransformBroadcaster static_tf;
  publish_static_frames(static_tf);
  rostest::Child aligned = start_node(session, "s3m_aligned", true), plain = start_node(session, "s3m_plain", false);
  ros::NodeHandle& nh = session.nh();
  RealsensePublisher cam(nh);
  PoseRecorder<PoseStamped> poses(nh, "/s3m_aligned/camera/pose");
  ASSERT_TRUE(wait_for([&] { return cam.connected(2) && poses.connected(); }, 60s))
      << log("s3m_aligned") << log("s3m_plain");

  constexpr int kFrames = 15;
  const sim::Simulation sim = rostest::office_flight(kFrames);
  const io::DepthToColour to_depth_camera(sim.camera(), d4xx_depth_camera(), kT_c_d.inverse());
  cam.publish_depth_info();
  io::Trajectory gt, est;
  bool behind = false;  // a wait timed out (the checks below fail): wait briefly from then on
  for (int i = 0; i < kFrames; ++i) {
    const RgbdFrame f = sim.frame(i);
    cam.publish(f, sim.camera(), to_depth_camera);
    gt.push_back({f.t_s, sim.trajectory().samples[i].T_w_c});
    behind = behind || !wait_for([&] { return poses.has(stamp_key(f.t_s)); }, behind ? 500ms : 20s);
  }
  for (const auto& [t, T] : poses.poses()) est.push_back({t, T});
  ASSERT_EQ(est.size(), static_cast<std::size_t>(kFrames)) << log("s3m_aligned");
  const eval::TrajectoryEvaluation ev = eval::evaluate_trajectory(gt, est, {}, "aligned");
  std::printf("~align_depth: %zu frames, ATE %.3f cm\n", est.size(), ev.ate.stats_m.rmse * 100);
  EXPECT_LT(ev.ate.stats_m.rmse, 0.01);  // measured 0.171 cm (0.175 with the TF reversed, which the log check below catches)
  const std::string aligned_log = log("s3m_aligned");
  for (const std::string& part :
       {std::string("depth camera 848x480 fx 425.0 at (-1.50, 0.03, 0.02) cm in the colour camera; its depth is "
                    "drawn into the colour camera's 640x480 pixels (/rs/depth/camera_info)"),  // T_c_d's translation: the TF looked up in the right direction
        "depth registered (aligned to colour by s3m_node, with /rs/depth/camera_info and TF " + kColourFrame + " <- " +
            kDepthFrame + ")"})
    EXPECT_NE(aligned_log.find(part), std::string::npos) << "missing '" << part << "' in\n" << aligned_log;

  // The node without ~align_depth stopped at its first frame and said why.
  ASSERT_TRUE(wait_for([&] { return !plain.running(); }, 30s)) << log("s3m_plain");
  const int status = plain.stop(1s);
  EXPECT_TRUE(WIFEXITED(status) && WEXITSTATUS(status) == 1) << log("s3m_plain");
  const std::string plain_log = log("s3m_plain");
  for (const char* part : {"the depth images are 848x480 but the colour images 640x480", "not registered to colour",
                           "align_depth:=true"})
    EXPECT_NE(plain_log.find(part), std::string::npos) << "missing '" << part << "' in\n" << plain_log;
  const int aligned_status = aligned.stop(60s);
  EXPECT_TRUE(WIFEXITED(aligned_status) && WEXITSTATUS(aligned_status) == 0) << log("s3m_aligned");
}

}  // namespace
}  // namespace s3m
