#include "node.hpp"

#include <filesystem>

#include <geometry_msgs/PoseStamped.h>
#include <message_filters/sync_policies/approximate_time.h>
#include <message_filters/sync_policies/exact_time.h>
#include <message_filters/synchronizer.h>
#include <nav_msgs/Odometry.h>
#include <sensor_msgs/PointCloud2.h>
#include <visualization_msgs/MarkerArray.h>
#include <boost/bind/bind.hpp>

#include "conversions.hpp"
#include "map_msgs.hpp"
#include "ros_params.hpp"
#include "s3m/core/error.hpp"
#include "s3m/io/camera_yaml.hpp"
#include "s3m/pipeline/cost_estimate.hpp"
#include "s3m/pipeline/factories.hpp"
#include "s3m/pipeline/outputs.hpp"
#include "s3m/pipeline/session_io.hpp"
#include "s3m/pipeline/unregistered_depth.hpp"

namespace s3m::ros1 {
namespace {

namespace mf = message_filters;
using boost::placeholders::_1;
using boost::placeholders::_2;
using boost::placeholders::_3;
using boost::placeholders::_4;
using sensor_msgs::CameraInfo;
using sensor_msgs::Image;

// A synchronizer of Policy over the given subscribers, calling cb; type-erased for the node.
template <typename Policy, typename Callback, typename... Subs>
std::shared_ptr<void> make_sync(int queue, Callback cb, Subs&... subs) {
  auto sync = std::make_shared<mf::Synchronizer<Policy>>(Policy(queue), subs...);
  sync->registerCallback(cb);
  return sync;
}

geometry_msgs::TransformStamped stamped(const SE3& T, const ros::Time& t, const std::string& parent,
                                        const std::string& child) {
  geometry_msgs::TransformStamped m;
  m.header.stamp = t;
  m.header.frame_id = parent;
  m.child_frame_id = child;
  m.transform = to_transform(T);
  return m;
}

nav_msgs::Odometry odometry(const SE3& T, const ros::Time& t, const std::string& parent,
                            const std::string& child) {
  nav_msgs::Odometry o;
  o.header.stamp = t;
  o.header.frame_id = parent;
  o.child_frame_id = child;
  o.pose.pose = to_pose(T);
  return o;
}

}  // namespace

NodeParams read_node_params(const ros::NodeHandle& pnh) {
  NodeParams p;
  p.config = config_from_params(pnh);
  p.config.threads.deterministic = true;  // processed inline: see node.hpp
  pnh.param("map_frame", p.map_frame, p.map_frame);
  pnh.param("odom_frame", p.odom_frame, p.odom_frame);
  pnh.param("base_frame", p.base_frame, p.base_frame);
  pnh.param("use_odom_tf", p.use_odom_tf, p.use_odom_tf);
  pnh.param("T_c_r_from_tf", p.T_c_r_from_tf, p.T_c_r_from_tf);
  pnh.param("publish_camera_tf", p.publish_camera_tf, p.publish_camera_tf);
  pnh.param("use_labels", p.use_labels, p.use_labels);
  pnh.param("approximate_sync", p.approximate_sync, p.approximate_sync);
  pnh.param("queue_size", p.queue_size, p.queue_size);
  pnh.param("map_every_n_frames", p.map_every_n_frames, p.map_every_n_frames);
  pnh.param("camera_bf", p.camera_bf, p.camera_bf);
  pnh.param("camera_from_config", p.camera_from_config, p.camera_from_config);
  pnh.param("align_depth", p.align_depth, p.align_depth);
  pnh.param("output_dir", p.output_dir, p.output_dir);
  pnh.param("save_on_exit", p.save_on_exit, p.save_on_exit);
  pnh.param("map", p.map, p.map);
  pnh.param("localize_only", p.localize_only, p.localize_only);
  pnh.param("force", p.force, p.force);
  require(p.queue_size > 0, "~queue_size must be > 0");
  require(!p.localize_only || !p.map.empty(), "~localize_only needs ~map (the saved run to localise in)");
  require(p.map.empty() ||
              std::filesystem::is_regular_file(std::filesystem::path(p.map) / pipeline::kSlamMapFile),
          "~map: '" + p.map + "' holds no " + pipeline::kSlamMapFile +
              " (expected a folder s3m run --out, ~save_map or save_on_exit wrote)");
  require(p.map_every_n_frames > 0, "~map_every_n_frames must be > 0");
  return p;
}

S3mNode::S3mNode(ros::NodeHandle nh, ros::NodeHandle pnh)
    : nh_(nh), pnh_(pnh), params_(read_node_params(pnh)) {
  const int q = params_.queue_size;
  rgb_sub_.subscribe(nh_, "rgb/image", q);
  depth_sub_.subscribe(nh_, "depth/image", q);
  info_sub_.subscribe(nh_, "rgb/camera_info", q);
  if (params_.use_labels) {
    labels_sub_.subscribe(nh_, "labels/image", q);
    // boost::bind (not a lambda): the synchronizer calls with 9 arguments, bind drops the unused.
    const auto cb = boost::bind(&S3mNode::on_frame, this, _1, _2, _3, _4);
    sync_ = params_.approximate_sync
                ? make_sync<mf::sync_policies::ApproximateTime<Image, Image, CameraInfo, Image>>(
                      q, cb, rgb_sub_, depth_sub_, info_sub_, labels_sub_)
                : make_sync<mf::sync_policies::ExactTime<Image, Image, CameraInfo, Image>>(
                      q, cb, rgb_sub_, depth_sub_, info_sub_, labels_sub_);
  } else {
    const auto cb = boost::bind(&S3mNode::on_frame, this, _1, _2, _3, ImageCPtr());
    sync_ = params_.approximate_sync
                ? make_sync<mf::sync_policies::ApproximateTime<Image, Image, CameraInfo>>(
                      q, cb, rgb_sub_, depth_sub_, info_sub_)
                : make_sync<mf::sync_policies::ExactTime<Image, Image, CameraInfo>>(q, cb, rgb_sub_,
                                                                                    depth_sub_, info_sub_);
  }
  if (params_.align_depth)
    depth_info_sub_ = nh_.subscribe("depth/camera_info", 2, &S3mNode::on_depth_info, this);
  cam_odom_ = pnh_.advertise<nav_msgs::Odometry>("camera/odom", 10);
  cam_pose_ = pnh_.advertise<geometry_msgs::PoseStamped>("camera/pose", 10);
  robot_odom_ = pnh_.advertise<nav_msgs::Odometry>("robot/odom", 10);
  robot_pose_ = pnh_.advertise<geometry_msgs::PoseStamped>("robot/pose", 10);
  markers_ = pnh_.advertise<visualization_msgs::MarkerArray>("map/markers", 1, /*latch=*/true);
  cloud_ = pnh_.advertise<sensor_msgs::PointCloud2>("map/cloud", 1, /*latch=*/true);
  seg_ = pnh_.advertise<Image>("segmentation", 2);
  labels_ = pnh_.advertise<Image>("labels", 2);
  query_result_ = pnh_.advertise<std_msgs::String>("query_result", 10);
  query_markers_ = pnh_.advertise<visualization_msgs::MarkerArray>("query_markers", 1, true);
  query_sub_ = pnh_.subscribe("query", 10, &S3mNode::on_query, this);
  save_srv_ = pnh_.advertiseService("save_map", &S3mNode::save_map, this);
  const std::string extra =
      std::string(params_.use_labels ? " (+ labels/image)" : "") +
      (params_.align_depth ? " (+ " + depth_info_sub_.getTopic() + ", ~align_depth)" : "");
  ROS_INFO("s3m_node: waiting for %s, %s and %s%s", rgb_sub_.getTopic().c_str(),
           depth_sub_.getTopic().c_str(), info_sub_.getTopic().c_str(), extra.c_str());
}

S3mNode::~S3mNode() {
  try {
    shutdown();
  } catch (const std::exception& e) {
    ROS_ERROR("s3m_node: %s", e.what());
  }
}

void S3mNode::on_frame(const ImageCPtr& rgb, const ImageCPtr& depth,
                       const sensor_msgs::CameraInfoConstPtr& info, const ImageCPtr& labels) {
  if (finished_) return;
  if (params_.align_depth && !pipeline_ && !depth_info_) {  // a driver publishes it with every depth image
    ROS_WARN_THROTTLE(2.0, "s3m_node: ~align_depth: waiting for %s (the depth camera's intrinsics)",
                      depth_info_sub_.getTopic().c_str());
    return;
  }
  try {
    RgbdFrame f;
    f.index = frames_++;
    f.t_s = to_seconds(rgb->header.stamp);
    f.depth_dt_s = to_seconds(depth->header.stamp) - f.t_s;
    f.rgb = colour_to_bgr(*rgb);
    f.depth_m = depth_to_metres(*depth);
    if (labels) f.labels = labels_to_ids(*labels);
    if (!pipeline_) start(*info, rgb->header.frame_id, depth->header.frame_id, f);
    if (to_colour_) f.depth_m = (*to_colour_)(f.depth_m);
    stamp_ = rgb->header.stamp;
    pipeline_->process(std::move(f));  // inline: on_outcome() runs before this returns
    if (frames_ % params_.map_every_n_frames == 0) publish_map(stamp_);
  } catch (const std::exception& e) {
    // A frame the pipeline refuses (wrong size, encoding) is a configuration error: stop loudly.
    ROS_FATAL("s3m_node: frame %d: %s", frames_ - 1, e.what());
    failed_ = true;
    ros::shutdown();
  }
}

void S3mNode::start(const CameraInfo& info, const std::string& camera_frame, const std::string& depth_frame,
                    const RgbdFrame& first) {
  pipeline::PipelineConfig& c = params_.config;
  std::string camera_note;
  const PinholeCamera camera =
      live_camera(info, c.dataset.camera, params_.camera_from_config, params_.camera_bf, camera_note);
  ROS_INFO("s3m_node: %s", camera_note.c_str());
  if (first.rgb.cols != camera.width || first.rgb.rows != camera.height)
    throw Error("the colour images are " + std::to_string(first.rgb.cols) + "x" +
                std::to_string(first.rgb.rows) + " but the camera is " + std::to_string(camera.width) + "x" +
                std::to_string(camera.height) + " (" + camera_note + ")");
  std::string registered_by;
  if (params_.align_depth)
    registered_by = start_alignment(camera_frame, depth_frame, camera);
  else if (first.depth_m.cols != camera.width || first.depth_m.rows != camera.height)
    throw Error(
        "the depth images are " + std::to_string(first.depth_m.cols) + "x" +
        std::to_string(first.depth_m.rows) + " but the colour images " + std::to_string(camera.width) + "x" +
        std::to_string(camera.height) +
        ": the depth is not registered to colour; launch the driver with depth aligned to colour "
        "(realsense2_camera align_depth:=true) or set ~align_depth:=true (depth/camera_info and the TF "
        "between the depth and colour frames then place the depth camera)");
  // A live stream offers one frame before the first is processed (s3m run checks six).
  ROS_INFO("s3m_node: depth %s",
           pipeline::resolve_depth_registration(c, {first}, camera, registered_by).c_str());
  // As s3m run does before its first frame: refuse settings that would take seconds per frame and
  // outgrow the memory (ROS_FATAL and exit 1 from on_frame), unless ~force.
  pipeline::check_cost(c, camera, params_.force, "~force:=true");
  camera_frame_ = camera_frame.empty() ? "camera" : camera_frame;
  if (params_.T_c_r_from_tf) {
    const auto T_r_c =
        tf_buffer_.lookupTransform(params_.base_frame, camera_frame_, ros::Time(0), ros::Duration(2.0));
    c.slam.T_c_r = from_transform(T_r_c.transform).inverse();
  } else if (params_.publish_camera_tf) {
    static_tf_.sendTransform(
        stamped(c.slam.T_c_r.inverse(), ros::Time::now(), params_.base_frame, camera_frame_));
  }
  // The config's segmenter section; `auto` (no preset) = the real-image model unless the stream
  // carries the simulator's label images.
  const pipeline::SegmenterChoice choice =
      pipeline::choose_segmenter({}, c, pipeline::simulator_sign("", params_.use_labels));
  auto segmenter = pipeline::make_segmenter(choice, c, params_.use_labels);
  const std::string segmenter_name = segmenter ? segmenter->name() : "none";
  auto map = std::make_unique<pipeline::MapIntegrator>(c.map, c.dynamic.map_exclusions());
  auto poses = pipeline::make_slam_poses(camera, c);
  const std::filesystem::path saved(params_.map);
  if (!params_.map.empty())
    pipeline::load_session_map(*poses, (saved / pipeline::kSlamMapFile).string(), params_.localize_only);
  pipeline_ =
      std::make_unique<pipeline::Pipeline>(c, camera, std::move(poses), std::move(segmenter), std::move(map));
  if (!params_.map.empty()) {
    if (std::filesystem::exists(saved / pipeline::kKeptCloudsFile))
      pipeline_->load_session_clouds((saved / pipeline::kKeptCloudsFile).string());
    // The saved run's `map` frame: its robot at its first keyframe (the SLAM world's origin).
    T_map_w_ = c.slam.T_c_r.inverse();
    ROS_INFO("s3m_node: continuing in %s%s", params_.map.c_str(),
             params_.localize_only ? " (localisation only)" : "");
  }
  pipeline_->set_frame_listener([this](const pipeline::FrameOutcome& o, const RgbdFrame&,
                                       const semantics::LabelMap& l) { on_outcome(o, l); });
  ROS_INFO("s3m_node: started (%dx%d, fx %.1f, segmenter %s (%s), config %s)", camera.width, camera.height,
           camera.fx, segmenter_name.c_str(), choice.reason.c_str(),
           c.source.empty() ? "defaults" : c.source.c_str());
}

std::string S3mNode::start_alignment(const std::string& colour_frame, const std::string& depth_frame,
                                     const PinholeCamera& colour) {
  const std::string frame = depth_frame.empty() ? depth_info_->header.frame_id : depth_frame;
  if (colour_frame.empty() || frame.empty())
    throw Error(
        "~align_depth: the colour and depth images need frame_ids to place one camera in the other "
        "(colour '" +
        colour_frame + "', depth '" + frame + "')");
  SE3 T_c_d;
  try {
    T_c_d = from_transform(
        tf_buffer_.lookupTransform(colour_frame, frame, ros::Time(0), ros::Duration(2.0)).transform);
  } catch (const tf2::TransformException& e) {
    throw Error("~align_depth: no TF from the depth frame " + frame + " to the colour frame " + colour_frame +
                ": " + e.what() + " (the driver's static transforms, e.g. realsense2_camera's /tf_static)");
  }
  const PinholeCamera depth = camera_from_info(*depth_info_, PinholeCamera{}.bf);
  to_colour_ = std::make_shared<const io::DepthToColour>(depth, colour, T_c_d);
  ROS_INFO("s3m_node: %s (%s)", to_colour_->describe().c_str(), depth_info_sub_.getTopic().c_str());
  return "s3m_node, with " + depth_info_sub_.getTopic() + " and TF " + colour_frame + " <- " + frame;
}

void S3mNode::on_outcome(const pipeline::FrameOutcome& o, const semantics::LabelMap& labels) {
  if (!labels.empty()) {
    const Stamp s{stamp_, camera_frame_};
    if (seg_.getNumSubscribers() > 0)
      seg_.publish(segmentation_image(labels, pipeline_->map()->tree().classes(), s));
    if (labels_.getNumSubscribers() > 0) labels_.publish(label_image(labels, s));
  }
  if (!o.tracked) {
    ROS_WARN_THROTTLE(2.0, "s3m_node: frame %d not tracked (%s)", o.index, to_string(o.state));
    return;
  }
  if (o.detached) {  // a SLAM sub-map's own frame, not the map's: nothing to publish until it merges
    ROS_WARN_THROTTLE(2.0, "s3m_node: frame %d tracked in a new sub-map, not merged into the map yet",
                      o.index);
    return;
  }
  publish_poses(o.T_w_c, stamp_);
}

void S3mNode::publish_poses(const SE3& T_w_c, const ros::Time& t) {
  const SE3& T_c_r = params_.config.slam.T_c_r;
  if (!T_map_w_) T_map_w_ = robot_pose(T_w_c, T_c_r).inverse();
  const SE3 T_map_c = *T_map_w_ * T_w_c, T_map_r = robot_pose(T_map_c, T_c_r);
  const std::string& map = params_.map_frame;
  cam_odom_.publish(odometry(T_map_c, t, map, camera_frame_));
  robot_odom_.publish(odometry(T_map_r, t, map, params_.base_frame));
  geometry_msgs::PoseStamped p;
  p.header.stamp = t, p.header.frame_id = map;
  p.pose = to_pose(T_map_c);
  cam_pose_.publish(p);
  p.pose = to_pose(T_map_r);
  robot_pose_.publish(p);
  // REP 105: map -> odom -> base_link. Without another odometry source odom = map.
  if (params_.odom_frame.empty()) {
    tf_.sendTransform(stamped(T_map_r, t, map, params_.base_frame));
  } else if (params_.use_odom_tf) {
    try {
      const auto T_o_r =
          tf_buffer_.lookupTransform(params_.odom_frame, params_.base_frame, t, ros::Duration(0.1));
      tf_.sendTransform(
          stamped(T_map_r * from_transform(T_o_r.transform).inverse(), t, map, params_.odom_frame));
    } catch (const tf2::TransformException& e) {
      ROS_WARN_THROTTLE(2.0, "s3m_node: no %s -> %s at this frame: %s", params_.odom_frame.c_str(),
                        params_.base_frame.c_str(), e.what());
    }
  } else {
    tf_.sendTransform({stamped(SE3::Identity(), t, map, params_.odom_frame),
                       stamped(T_map_r, t, params_.odom_frame, params_.base_frame)});
  }
}

void S3mNode::publish_map(const ros::Time& t) {
  if (!pipeline_ || !pipeline_->map() || !T_map_w_) return;
  const mapping::SemanticOcTree& tree = pipeline_->map()->tree();
  const Stamp s{t, params_.map_frame};
  markers_.publish(map_markers(tree, *T_map_w_, s));
  cloud_.publish(map_cloud(tree, *T_map_w_, s));
}

}  // namespace s3m::ros1
