// `s3m tum2bag DIR --out FILE.bag`: a TUM-layout directory (e.g. from `s3m sim`) as a ROS1 bag, and
// the rosbag options of `s3m run`. Both need a ROS build (-DS3M_WITH_ROS=ON with ROS installed).
#include <iostream>

#include "commands.hpp"
#include "ros_support.hpp"
#include "s3m/core/error.hpp"
#ifdef S3M_HAVE_ROS
#include "bag_source.hpp"
#include "bag_writer.hpp"
#endif

namespace s3m::apps {

namespace {

[[noreturn, maybe_unused]] void no_ros(const std::string& what) {
  throw Error(what +
              ": this s3m binary was built without ROS; install ROS with scripts/setup.sh --with-ros "
              "and configure with -DS3M_WITH_ROS=ON");
}

struct Tum2BagArgs {
  std::string dataset, out, depth_encoding = "32FC1", frame = "camera_rgb_optical_frame";
  RosbagArgs topics{
      "", "/camera/rgb/image_color", "/camera/depth/image", "/camera/rgb/camera_info", "", "/groundtruth"};
  bool labels = true;
  long max_frames = -1;
};

#ifdef S3M_HAVE_ROS
ros1::BagTopics bag_topics(const RosbagArgs& a) {
  return {a.rgb_topic, a.depth_topic, a.camera_info_topic, a.labels_topic, a.gt_topic};
}
#endif

}  // namespace

void add_rosbag_options(CLI::App& cmd, RosbagArgs& a) {
  cmd.add_option("--rosbag", a.bag, "read frames from a ROS1 bag instead of a directory (ROS builds)");
  cmd.add_option("--rgb-topic", a.rgb_topic,
                 "with --rosbag or a ROS 2 recording: colour sensor_msgs/Image topic (default: recognised "
                 "from the bag's topics: TUM "
                 "RGB-D, RealSense SDK, realsense2_camera, openni_launch, Azure Kinect, orbbec_camera)");
  cmd.add_option("--depth-topic", a.depth_topic,
                 "with --rosbag or a ROS 2 recording: depth image topic registered to colour (16UC1 mm or "
                 "32FC1 m; default: recognised)");
  cmd.add_option(
      "--camera-info-topic", a.camera_info_topic,
      "with --rosbag or a ROS 2 recording: sensor_msgs/CameraInfo topic (default: recognised, or the colour "
      "topic's "
      "camera_info; a RealSense's or Azure Kinect's own calibration wins over the config's dataset.camera, "
      "which wins over other recordings'; \"none\": dataset.camera)");
  cmd.add_option("--labels-topic", a.labels_topic,
                 "with --rosbag or a ROS 2 recording: optional mono16 ground-truth class ids (oracle)");
  cmd.add_option("--gt-topic", a.gt_topic,
                 "with --rosbag or a ROS 2 recording: optional geometry_msgs/PoseStamped ground truth "
                 "(T_w_c; ROS 2: or nav_msgs/msg/Odometry)")
      ->capture_default_str();
}

std::function<std::unique_ptr<pipeline::FrameSource>(const pipeline::PipelineConfig&)> rosbag_source(
    const RosbagArgs& a) {
#ifdef S3M_HAVE_ROS
  return [a](const pipeline::PipelineConfig& c) {
    return ros1::open_bag_source(a.bag, bag_topics(a), c.dataset);
  };
#else
  (void)a;
  no_ros("--rosbag");
#endif
}

void register_tum2bag(CLI::App& app) {
  auto args = std::make_shared<Tum2BagArgs>();
  auto* cmd = app.add_subcommand("tum2bag", "Write a TUM-layout directory into a ROS1 bag (ROS builds)");
  cmd->add_option("dataset", args->dataset, "TUM-layout directory (e.g. written by s3m sim)")->required();
  cmd->add_option("--out", args->out, "bag file to write")->required();
  cmd->add_option("--rgb-topic", args->topics.rgb_topic)->capture_default_str();
  cmd->add_option("--depth-topic", args->topics.depth_topic)->capture_default_str();
  cmd->add_option("--camera-info-topic", args->topics.camera_info_topic)->capture_default_str();
  args->topics.labels_topic = "/camera/labels";
  cmd->add_option("--labels-topic", args->topics.labels_topic, "label images, when the sequence has them")
      ->capture_default_str();
  cmd->add_option("--gt-topic", args->topics.gt_topic, "ground truth (geometry_msgs/PoseStamped, \"\": none)")
      ->capture_default_str();
  cmd->add_option("--depth-encoding", args->depth_encoding, "32FC1 (metres, exact) or 16UC1 (millimetres)")
      ->check(CLI::IsMember({"32FC1", "16UC1"}))
      ->capture_default_str();
  cmd->add_option("--frame-id", args->frame, "header frame_id of the images")->capture_default_str();
  cmd->add_option("--max-frames", args->max_frames, "write at most N frames")->check(count_option());
  cmd->callback([args] {
#ifdef S3M_HAVE_ROS
    ros1::BagWriteOptions o;
    o.topics = bag_topics(args->topics);
    o.depth_encoding = args->depth_encoding;
    o.camera_frame = args->frame;
    o.max_frames = args->max_frames;
    const std::size_t n = ros1::write_tum_to_bag(args->dataset, args->out, o);
    std::cout << "wrote " << n << " frames to " << args->out << "\n";
#else
    no_ros("tum2bag");
#endif
  });
}

}  // namespace s3m::apps
