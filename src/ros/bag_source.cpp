#include "bag_source.hpp"

#include <algorithm>
#include <cmath>
#include <map>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include <geometry_msgs/PoseStamped.h>
#include <geometry_msgs/Transform.h>
#include <rosbag/bag.h>
#include <rosbag/view.h>
#include <sensor_msgs/CameraInfo.h>
#include <sensor_msgs/Image.h>
#include <spdlog/spdlog.h>
#include <std_msgs/Float32.h>
#include <tf2/buffer_core.h>
#include <tf2/exceptions.h>
#include <tf2_msgs/TFMessage.h>

#include "bag_recordings.hpp"
#include "conversions.hpp"
#include "s3m/core/error.hpp"
#include "s3m/core/input_file.hpp"
#include "s3m/io/association.hpp"
#include "s3m/io/camera_yaml.hpp"
#include "s3m/io/depth_to_colour.hpp"

namespace s3m::ros1 {
namespace {

struct Stamped {
  double t_s;
  std::size_t msg;  // index into Stream::msgs
};

// One image topic: its messages (valid while the Bag is open; not assignable, hence the index)
// and their header stamps in time order.
struct Stream {
  std::vector<rosbag::MessageInstance> msgs;
  std::vector<Stamped> by_time;
  bool empty() const { return msgs.empty(); }
};

template <typename Msg>
boost::shared_ptr<Msg> instantiate(const rosbag::MessageInstance& m, const std::string& bag) {
  auto p = m.instantiate<Msg>();
  if (!p)
    throw Error(bag + ": topic " + m.getTopic() + " carries " + m.getDataType() + " (expected " +
                ros::message_traits::DataType<Msg>::value() + ")");
  return p;
}

// The bag's topics of one message type with their message counts, for an error about a topic that
// is not there: a recorder's topic names (a RealSense bag's /device_0/sensor_1/Color_0/image/data)
// are what the user would otherwise have to dig out with `rosbag info`.
std::string topics_of_type(const rosbag::Bag& bag, const std::string& datatype) {
  std::map<std::string, std::size_t> counts;
  rosbag::View all(bag);  // getConnections() is not const
  for (const rosbag::ConnectionInfo* c : all.getConnections())
    if (c->datatype == datatype) counts[c->topic] = 0;
  for (auto& [topic, n] : counts) n = rosbag::View(bag, rosbag::TopicQuery(topic)).size();
  if (counts.empty()) return "; the bag has no " + datatype + " topic";
  std::string list;
  for (const auto& [topic, n] : counts)
    list += (list.empty() ? "" : ", ") + topic + " (" + std::to_string(n) + ")";
  return "; its " + datatype + " topics (messages): " + list;
}

// topic -> message type of every connection, for recognise_recording.
std::map<std::string, std::string> topic_types(const rosbag::Bag& bag) {
  std::map<std::string, std::string> out;
  rosbag::View all(bag);
  for (const rosbag::ConnectionInfo* c : all.getConnections()) out[c->topic] = c->datatype;
  return out;
}

template <typename Msg>
boost::shared_ptr<Msg> first_message(const rosbag::Bag& bag, const std::string& topic,
                                     const std::string& path) {
  for (const rosbag::MessageInstance& m : rosbag::View(bag, rosbag::TopicQuery(topic)))
    return instantiate<Msg>(m, path);
  return nullptr;
}

// Which topics to read: the ones given, or (none given) the recorder's, recognised by topic names.
BagRecording choose_topics(const rosbag::Bag& bag, const BagTopics& given, const std::string& path) {
  const std::map<std::string, std::string> types = topic_types(bag);
  BagRecording r;
  if (given.rgb.empty() && given.depth.empty()) {
    try {
      r = recognise_recording(types);
    } catch (const Error& e) {
      throw Error(path + ": " + e.what());
    }
  } else {
    const BagTopics tum;
    const std::string rgb = given.rgb.empty() ? tum.rgb : given.rgb,
                      depth = given.depth.empty() ? tum.depth : given.depth;
    std::optional<BagRecording> known;
    try {
      known = recording_with(types, rgb, depth);
    } catch (const Error& e) {
      throw Error(path + ": " + e.what());
    }
    if (known) {  // one camera of several: its recorder's other topics as without topic options
      r = *known;
      r.recorder += ", topics given";
      if (!given.camera_info.empty() && given.camera_info != "none") r.rgb_info = given.camera_info;
      return r;
    }
    r.recorder = "topics given";
    r.rgb = rgb;
    r.depth = depth;
    // The colour topic's sibling camera_info (image_raw -> camera_info), as drivers name them.
    const std::string sibling = r.rgb.substr(0, r.rgb.rfind('/') + 1) + "camera_info";
    const auto it = types.find(sibling);
    if (it != types.end() && it->second == "sensor_msgs/CameraInfo") r.rgb_info = sibling;
  }
  if (!given.camera_info.empty() && given.camera_info != "none") r.rgb_info = given.camera_info;
  return r;
}

Stream image_index(const rosbag::Bag& bag, const std::string& path, const std::string& topic) {
  Stream out;
  for (const rosbag::MessageInstance& m : rosbag::View(bag, rosbag::TopicQuery(topic))) {
    out.by_time.push_back(
        {to_seconds(instantiate<sensor_msgs::Image>(m, path)->header.stamp), out.msgs.size()});
    out.msgs.push_back(m);
  }
  std::stable_sort(out.by_time.begin(), out.by_time.end(),
                   [](const Stamped& a, const Stamped& b) { return a.t_s < b.t_s; });
  return out;
}

sensor_msgs::ImageConstPtr image_at(const Stream& s, std::size_t i, const std::string& path) {
  return instantiate<sensor_msgs::Image>(s.msgs[s.by_time[i].msg], path);
}

class BagFrameSource final : public pipeline::FrameSource {
 public:
  BagFrameSource(const std::string& path, const BagTopics& topics, const pipeline::DatasetConfig& dataset)
      : path_(path) {
    require_input_file(path, "a ROS1 bag file (--rosbag)");
    try {
      bag_.open(path, rosbag::bagmode::Read);
    } catch (const rosbag::BagException& e) {
      throw Error("--rosbag " + path + ": " + e.what());
    }
    const BagRecording rec = choose_topics(bag_, topics, path);
    rgb_ = image_index(bag_, path, rec.rgb);
    depth_ = image_index(bag_, path, rec.depth);
    const std::string images = "sensor_msgs/Image";
    if (rgb_.empty())
      throw Error(path + ": no messages on the colour topic " + rec.rgb + " (--rgb-topic)" +
                  topics_of_type(bag_, images));
    if (depth_.empty())
      throw Error(path + ": no messages on the depth topic " + rec.depth + " (--depth-topic)" +
                  topics_of_type(bag_, images));
    if (!topics.labels.empty()) labels_ = image_index(bag_, path, topics.labels);
    // The colour CameraInfo, read once: the camera, and its frame_id places a raw depth camera.
    const auto rgb_info =
        rec.rgb_info.empty() ? nullptr : first_message<sensor_msgs::CameraInfo>(bag_, rec.rgb_info, path);
    const io::CameraFile camera_file =
        read_camera(rec, rgb_info, topics.camera_info, dataset.camera, camera_source_);
    camera_ = camera_file.camera;
    read_depth_units(rec.depth_units);
    registered_by_ = rec.registered_by;
    // A camera file with a depth_camera section (7-Scenes' preset 7scenes_kinect_v1) says the depth
    // images are another camera's, whatever the topics' names suggest (a 7-Scenes folder written
    // as a TUM bag by `s3m tum2bag` has TUM's registered-looking topics).
    if (const std::optional<io::DepthCamera>& config_depth = camera_file.depth) {
      to_colour_ = std::make_shared<io::DepthToColour>(config_depth->camera, camera_, config_depth->T_c_d);
      spdlog::info("{}: {}", path, to_colour_->describe());
      registered_by_ = "s3m, with the depth_camera of dataset.camera " + dataset.camera;
    } else if (!rec.registered()) {
      align_depth(rec, rgb_info ? rgb_info->header.frame_id : "");
      registered_by_ = "s3m, with the recording's depth camera and extrinsics";
    }
    read_groundtruth(topics.groundtruth);
    pair(dataset.max_dt_s);
    layout_ = fmt::format(
        "ROS bag, {}: colour {}, depth {} ({}{})", rec.recorder, rec.rgb, rec.depth,
        rec.registered() ? "registered to colour" : "aligned to colour here",
        rec.depth_units.empty() ? "" : fmt::format(", depth unit {:.3g} mm", metres_per_unit_ * 1e3));
    spdlog::info("{}: {}, {} frames", path, layout_, pairs_.size());
  }

  RgbdFrame load(std::size_t index) const override {
    require(index < pairs_.size(), path_ + ": frame " + std::to_string(index) + " requested, the bag has " +
                                       std::to_string(pairs_.size()) + " colour/depth pairs");
    const Pair& p = pairs_[index];
    RgbdFrame f;
    f.index = static_cast<int>(index);
    f.t_s = rgb_.by_time[p.rgb].t_s;
    f.depth_dt_s = depth_.by_time[p.depth].t_s - f.t_s;
    f.rgb = colour_to_bgr(*image_at(rgb_, p.rgb, path_));
    f.depth_m = depth_to_metres(*image_at(depth_, p.depth, path_), metres_per_unit_);
    if (to_colour_) f.depth_m = aligned(f.depth_m, f.index);
    if (p.labels >= 0) f.labels = labels_to_ids(*image_at(labels_, p.labels, path_));
    check_size(f);
    return f;
  }
  std::size_t size() const override { return pairs_.size(); }
  const PinholeCamera& camera() const override { return camera_; }
  const io::Trajectory& groundtruth() const override { return groundtruth_; }
  bool has_labels() const override { return !labels_.empty(); }
  std::string name() const override { return path_; }
  std::string eval_dir() const override { return ""; }
  double timestamp(std::size_t index) const override { return rgb_.by_time[pairs_.at(index).rgb].t_s; }
  std::string layout() const override { return layout_; }
  std::string camera_source() const override { return camera_source_; }
  std::string depth_registered_by() const override { return registered_by_; }
  std::string depth_camera() const override { return to_colour_ ? to_colour_->describe() : ""; }

 private:
  struct Pair {
    long rgb, depth, labels;
  };

  // Precedence: a camera-info topic given on the command line ("none": the config's camera); a
  // device's factory calibration (rec.device_calibration); the config's dataset.camera (a
  // calibrated preset: TUM's and openni's CameraInfo hold the driver's uncalibrated defaults); the
  // recording's CameraInfo. What was not used and why is logged. Returns the colour camera, with the
  // config file's depth camera when that file is the one used.
  io::CameraFile read_camera(const BagRecording& rec, sensor_msgs::CameraInfoConstPtr rgb_info,
                             const std::string& given_topic, const std::string& config_camera,
                             std::string& source) const {
    const bool none = given_topic == "none";
    if (none && config_camera.empty())
      throw Error(path_ + ": --camera-info-topic none, but the config sets no dataset.camera");
    const std::string topic = none ? "" : rec.rgb_info;
    const auto info = none ? nullptr : rgb_info;
    if (!given_topic.empty() && !none && !info)
      throw Error(path_ + ": no messages on the camera-info topic " + topic + " (--camera-info-topic)" +
                  topics_of_type(bag_, "sensor_msgs/CameraInfo"));
    const bool use_info = info && (config_camera.empty() || !given_topic.empty() || rec.device_calibration);
    io::CameraFile file;
    PinholeCamera& c = file.camera;
    if (use_info) {
      c = camera_from_info(*info, PinholeCamera{}.bf), source = "CameraInfo on " + topic;
      if (!config_camera.empty())
        spdlog::info(
            "{}: camera from the recording's CameraInfo ({}), not the config's dataset.camera {}{}; "
            "--camera-info-topic none uses dataset.camera",
            path_, topic, config_camera, given_topic.empty() ? " (the device's own calibration)" : "");
    } else if (!config_camera.empty()) {
      file = io::load_camera_file(config_camera), source = "dataset.camera " + config_camera;
      if (info && !info_matches(*info, c))
        spdlog::warn(
            "{}: the config's camera ({}: {}x{}, fx {:.1f}) is not the recording's ({}: {}x{}, fx {:.1f}); "
            "--camera-info-topic {} uses the recording's",
            path_, config_camera, c.width, c.height, c.fx, topic, info->width, info->height, info->K[0],
            topic);
    } else {
      throw Error(path_ + ": no camera: the bag has no CameraInfo for its colour topic " + rec.rgb +
                  "; pass --camera-info-topic or set dataset.camera in the config" +
                  topics_of_type(bag_, "sensor_msgs/CameraInfo"));
    }
    // The first colour image must fit the camera: said now, not at frame 0 of the run.
    const auto first = image_at(rgb_, 0, path_);
    if (first->width != static_cast<unsigned>(c.width) || first->height != static_cast<unsigned>(c.height))
      throw Error(
          path_ + ": the colour images are " + std::to_string(first->width) + "x" +
          std::to_string(first->height) + " but the camera (" + source + ") is " + std::to_string(c.width) +
          "x" + std::to_string(c.height) +
          (info && !use_info ? "; --camera-info-topic " + topic + " uses the recording's calibration" : ""));
    return file;
  }

  // The RealSense SDK records its depth unit (0.001 m by default; 0.0001 m in its high-accuracy modes).
  void read_depth_units(const std::string& topic) {
    if (topic.empty()) return;
    const auto units = first_message<std_msgs::Float32>(bag_, topic, path_);
    if (!units) return;
    if (!(units->data > 0.0f) || units->data > 1.0f)
      throw Error(path_ + ": " + topic + " = " + std::to_string(units->data) +
                  " (expected metres per depth unit in (0, 1])");
    metres_per_unit_ = units->data;
  }

  // Raw depth: the depth camera's intrinsics and where it sits, for io::DepthToColour.
  void align_depth(const BagRecording& rec, const std::string& colour_frame) {
    const auto info = first_message<sensor_msgs::CameraInfo>(bag_, rec.depth_info, path_);
    if (!info) throw Error(path_ + ": no messages on " + rec.depth_info + " (the depth camera's intrinsics)");
    const PinholeCamera depth_camera = camera_from_info(*info, PinholeCamera{}.bf);
    SE3 T_c_d;
    if (!rec.depth_extrinsics
             .empty()) {  // RealSense SDK: both transforms map the reference stream into theirs
      const auto T_rgb_ref = first_message<geometry_msgs::Transform>(bag_, rec.rgb_extrinsics, path_);
      const auto T_depth_ref = first_message<geometry_msgs::Transform>(bag_, rec.depth_extrinsics, path_);
      if (!T_rgb_ref || !T_depth_ref)
        throw Error(path_ + ": no messages on " + rec.rgb_extrinsics + " / " + rec.depth_extrinsics);
      T_c_d = from_transform(*T_rgb_ref) * from_transform(*T_depth_ref).inverse();
    } else {
      T_c_d = static_transform(colour_frame, info->header.frame_id);
    }
    to_colour_ = std::make_shared<io::DepthToColour>(depth_camera, camera_, T_c_d);
    spdlog::info("{}: {}", path_, to_colour_->describe());
  }

  // T_c_d from the bag's /tf_static (a driver's static camera frames), colour frame <- depth frame.
  SE3 static_transform(const std::string& colour_frame, const std::string& depth_frame) const {
    if (colour_frame.empty() || depth_frame.empty())
      throw Error(path_ +
                  ": the depth is not registered to colour and the CameraInfo messages name no frame_id");
    tf2::BufferCore tf;
    for (const rosbag::MessageInstance& m : rosbag::View(bag_, rosbag::TopicQuery("/tf_static"))) {
      const auto msg =
          instantiate<tf2_msgs::TFMessage>(m, path_);  // held: a range-for would not keep it alive
      for (const auto& t : msg->transforms) tf.setTransform(t, "bag", true);
    }
    try {
      return from_transform(tf.lookupTransform(colour_frame, depth_frame, ros::Time(0)).transform);
    } catch (const tf2::TransformException& e) {
      throw Error(path_ + ": the depth (" + depth_frame + ") is not registered to colour (" + colour_frame +
                  ") and /tf_static does not connect them: " + e.what() +
                  "; record /tf_static, or the driver's depth aligned to colour");
    }
  }

  cv::Mat aligned(const cv::Mat& depth_m, int index) const {
    const PinholeCamera& d = to_colour_->depth_camera();
    if (depth_m.cols != d.width || depth_m.rows != d.height)
      throw Error(path_ + ": frame " + std::to_string(index) + " depth image is " +
                  std::to_string(depth_m.cols) + "x" + std::to_string(depth_m.rows) +
                  " (expected the depth camera's " + std::to_string(d.width) + "x" +
                  std::to_string(d.height) + ")");
    return (*to_colour_)(depth_m);
  }

  void read_groundtruth(const std::string& topic) {
    if (topic.empty()) return;
    for (const rosbag::MessageInstance& m : rosbag::View(bag_, rosbag::TopicQuery(topic))) {
      const auto p = instantiate<geometry_msgs::PoseStamped>(m, path_);
      groundtruth_.push_back({to_seconds(p->header.stamp), from_pose(p->pose)});
    }
    std::stable_sort(groundtruth_.begin(), groundtruth_.end(),
                     [](const StampedPose& a, const StampedPose& b) { return a.t_s < b.t_s; });
  }

  void pair(double max_dt_s) {
    const auto stamps = [](const Stream& s) {
      std::vector<double> t;
      for (const Stamped& m : s.by_time) t.push_back(m.t_s);
      return t;
    };
    const io::StampPairs p = io::pair_by_stamp(stamps(rgb_), stamps(depth_), stamps(labels_), max_dt_s);
    for (const io::StampPair& q : p.pairs) pairs_.push_back({long(q.rgb), long(q.depth), q.labels});
    const std::size_t skipped = p.skipped;
    if (skipped > 0)
      spdlog::warn("{}: {} colour images without a depth image within {} s were skipped", path_, skipped,
                   max_dt_s);
    if (pairs_.empty())
      throw Error(path_ + ": no colour/depth pairs within " + std::to_string(max_dt_s) + " s");
  }

  void check_size(const RgbdFrame& f) const {
    for (const cv::Mat* m : {&f.rgb, &f.depth_m, &f.labels})
      if (!m->empty() && (m->cols != camera_.width || m->rows != camera_.height))
        throw Error(path_ + ": frame " + std::to_string(f.index) + " image is " + std::to_string(m->cols) +
                    "x" + std::to_string(m->rows) + " (expected the camera's " +
                    std::to_string(camera_.width) + "x" + std::to_string(camera_.height) + ")");
  }

  std::string path_, layout_, camera_source_, registered_by_;
  rosbag::Bag bag_;
  Stream rgb_, depth_, labels_;
  std::vector<Pair> pairs_;
  PinholeCamera camera_;
  double metres_per_unit_ = 1e-3;  // 16-bit depth: millimetres unless the recorder says otherwise
  std::shared_ptr<const io::DepthToColour> to_colour_;  // raw depth; null = registered
  io::Trajectory groundtruth_;
};

}  // namespace

std::unique_ptr<pipeline::FrameSource> open_bag_source(const std::string& bag_path, const BagTopics& topics,
                                                       const pipeline::DatasetConfig& dataset) {
  return std::make_unique<BagFrameSource>(bag_path, topics, dataset);
}

}  // namespace s3m::ros1
