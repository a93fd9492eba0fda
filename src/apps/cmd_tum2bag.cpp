// `s3m tum2bag DIR --out FILE.bag`: a TUM-layout directory (e.g. from `s3m sim`) as a ROS1 bag (a ROS
// build: -DS3M_WITH_ROS=ON with ROS installed) or, with --format mcap|db3, as a ROS 2 recording (every
// build); and the rosbag options of `s3m run`.
#include <iostream>

#include "commands.hpp"
#include "ros_support.hpp"
#include "s3m/core/error.hpp"
#include "s3m/io/dataset.hpp"
#include "s3m/pipeline/factories.hpp"
#include "s3m/rosbag2/dataset_writer.hpp"
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
  std::string dataset, out, depth_encoding = "32FC1", frame = "camera_rgb_optical_frame", format = "bag",
                            compression = "zstd";
  RosbagArgs topics{
      "", "/camera/rgb/image_color", "/camera/depth/image", "/camera/rgb/camera_info", "", "/groundtruth"};
  bool labels = true;
  long max_frames = -1;
};

// A ROS 2 recording, in every build: the folder's frames and, for a simulator sequence, its
// robot-to-camera mount on /tf_static.
std::size_t write_ros2(const Tum2BagArgs& a) {
  if (a.depth_encoding != "32FC1")
    throw Error("tum2bag --format " + a.format + ": depth is written as 32FC1 only");
  rosbag2::DatasetWriteOptions o;
  o.format = a.format;
  o.compression = a.compression;
  o.rgb_topic = a.topics.rgb_topic, o.depth_topic = a.topics.depth_topic;
  o.camera_info_topic = a.topics.camera_info_topic, o.labels_topic = a.topics.labels_topic;
  o.gt_topic = a.topics.gt_topic, o.frame_id = a.frame, o.max_frames = a.max_frames;
  o.T_c_r = pipeline::simulator_T_c_r(a.dataset);
  return rosbag2::write_dataset(io::Dataset::open(a.dataset), a.out, o);
}

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
  auto* cmd = app.add_subcommand(
      "tum2bag",
      "Write a TUM-layout directory into a ROS1 bag (ROS builds) or a ROS 2 recording (--format mcap|db3)");
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
  cmd->add_option(
         "--format", args->format,
         "bag: a ROS1 bag (ROS builds); mcap or db3: a ROS 2 recording (every build; --out FILE.mcap or "
         "FILE.db3; depth is always 32FC1)")
      ->check(CLI::IsMember({"bag", "mcap", "db3"}))
      ->capture_default_str();
  cmd->add_option("--compression", args->compression, "with --format mcap: chunk compression, zstd or none")
      ->check(CLI::IsMember({"zstd", "none"}))
      ->capture_default_str();
  cmd->callback([args] {
    if (args->format != "bag") {
      std::cout << "wrote " << write_ros2(*args) << " frames to " << args->out << "\n";
      return;
    }
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
