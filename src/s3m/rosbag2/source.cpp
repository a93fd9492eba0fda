#include "s3m/rosbag2/source.hpp"

#include <cmath>

#include <fmt/format.h>
#include <spdlog/spdlog.h>

#include "s3m/io/association.hpp"
#include "s3m/io/camera_yaml.hpp"
#include "s3m/io/depth_to_colour.hpp"
#include "s3m/rosbag2/camera_info.hpp"
#include "s3m/rosbag2/images.hpp"
#include "s3m/rosbag2/recording_index.hpp"

namespace s3m::rosbag2 {

void Rosbag2Topics::validate() const {
  require(rgb.empty() == depth.empty(), "ROS 2 topics: give both the colour and the depth topic, or neither");
}

namespace {

const std::string kImage = "sensor_msgs/msg/Image", kCompressed = "sensor_msgs/msg/CompressedImage";

// "/a (12 messages, 30.0 Hz), ..." of every topic of `type`, for an error about a missing topic.
std::string topics_of_type(const RecordingIndex& x, const std::string& type) {
  std::string list;
  for (const auto& [topic, s] : x.topics)
    if (s.type == type)
      list += fmt::format("{}{} ({} messages)", list.empty() ? "" : ", ", topic, s.messages);
  return list.empty() ? "; the recording has no " + type + " topic" : "; its " + type + " topics: " + list;
}

class Rosbag2FrameSource final : public Rosbag2Source {
 public:
  Rosbag2FrameSource(const std::string& path, const Rosbag2Topics& topics,
                     const pipeline::DatasetConfig& dataset)
      : path_(path), rec_(path) {
    topics.validate();
    RecordingIndex x = index_recording(rec_);
    try {
      set_ = choose_topics(x.types(), topics.rgb, topics.depth, topics.camera_info);
    } catch (const Error& e) {
      throw Error(path + ": " + e.what());
    }
    if (!topics.labels.empty()) set_.labels = topics.labels;
    rgb_ = take_images(x, set_.rgb, "colour", "--rgb-topic");
    depth_ = take_images(x, set_.depth, "depth", "--depth-topic");
    if (!set_.labels.empty()) labels_ = take_images(x, set_.labels, "labels", "--labels-topic");
    read_camera(x, topics.camera_info, dataset.camera);
    register_depth(x, dataset.camera);
    read_groundtruth(x, topics.groundtruth);
    find_robot(x);
    pair(dataset.max_dt_s);
    describe(x);
  }

  RgbdFrame load(std::size_t index) const override {
    require(index < pairs_.size(), path_ + ": frame " + std::to_string(index) +
                                       " requested, the recording has " + std::to_string(pairs_.size()) +
                                       " colour/depth pairs");
    const Pair& p = pairs_[index];
    RgbdFrame f;
    f.index = static_cast<int>(index);
    f.t_s = rgb_.msgs[p.rgb].t_s;
    f.depth_dt_s = depth_.msgs[p.depth].t_s - f.t_s;
    f.rgb = colour(rgb_.msgs[p.rgb].ref);
    f.depth_m = depth(depth_.msgs[p.depth].ref);
    if (to_colour_) f.depth_m = aligned(f.depth_m, f.index);
    if (p.labels >= 0) {
      const MessageRef& ref = labels_.msgs[p.labels].ref;
      const std::vector<std::uint8_t> b = rec_.read(ref);
      const std::string where = rec_.locate(ref) + " (" + set_.labels + ")";
      f.labels = label_image(decode_image({b.data(), b.size()}, where), where);
    }
    check_size(f);
    return f;
  }
  std::size_t size() const override { return pairs_.size(); }
  const PinholeCamera& camera() const override { return camera_; }
  const io::Trajectory& groundtruth() const override { return groundtruth_; }
  bool has_labels() const override { return !labels_.msgs.empty(); }
  std::string name() const override { return path_; }
  std::string eval_dir() const override { return ""; }
  double timestamp(std::size_t index) const override { return rgb_.msgs[pairs_.at(index).rgb].t_s; }
  std::string layout() const override { return layout_; }
  std::string camera_source() const override { return camera_source_; }
  std::string depth_registered_by() const override { return registered_by_; }
  std::string depth_camera() const override { return to_colour_ ? to_colour_->describe() : ""; }
  std::optional<SE3> T_c_r() const override { return T_c_r_; }
  std::string robot_frame() const override { return robot_frame_; }

 private:
  struct Stream {
    std::string topic;
    bool compressed = false;
    std::vector<StampedRef> msgs;  // by stamp
  };
  struct Pair {
    long rgb, depth, labels;
  };

  Stream take_images(RecordingIndex& x, const std::string& topic, const char* what,
                     const char* option) const {
    const auto t = x.topics.find(topic);
    if (t == x.topics.end())
      throw Error(path_ + ": no messages on the " + what + " topic " + topic + " (" + option + ")" +
                  topics_of_type(x, kImage) + topics_of_type(x, kCompressed));
    if (t->second.type != kImage && t->second.type != kCompressed)
      throw Error(path_ + ": the " + what + " topic " + topic + " carries " + t->second.type + " (expected " +
                  kImage + " or " + kCompressed + ")");
    return Stream{topic, t->second.type == kCompressed, std::move(x.images[topic])};
  }

  std::string where(const Stream& s, const MessageRef& ref) const {
    return rec_.locate(ref) + " (" + s.topic + ")";
  }

  cv::Mat colour(const MessageRef& ref) const {
    const std::vector<std::uint8_t> b = rec_.read(ref);
    const std::string w = where(rgb_, ref);
    return rgb_.compressed ? colour_image(decode_compressed_image({b.data(), b.size()}, w), w)
                           : colour_image(decode_image({b.data(), b.size()}, w), w);
  }
  cv::Mat depth(const MessageRef& ref) const {
    const std::vector<std::uint8_t> b = rec_.read(ref);
    const std::string w = where(depth_, ref);
    constexpr double kMillimetres = 1e-3;
    return depth_.compressed ? depth_image(decode_compressed_image({b.data(), b.size()}, w), kMillimetres, w)
                             : depth_image(decode_image({b.data(), b.size()}, w), kMillimetres, w);
  }

  // Precedence as for ROS 1 bags: a camera-info topic given ("none": the config's camera); a device's
  // factory calibration; the config's dataset.camera; the recording's CameraInfo.
  void read_camera(const RecordingIndex& x, const std::string& given, const std::string& config_camera) {
    const bool none = given == "none";
    if (none && config_camera.empty())
      throw Error(path_ + ": --camera-info-topic none, but the config sets no dataset.camera");
    const auto it = none ? x.first_info.end() : x.first_info.find(set_.rgb_info);
    const CameraInfo* info = it == x.first_info.end() ? nullptr : &it->second;
    if (const auto own = x.first_info.find(set_.rgb_info); own != x.first_info.end())
      camera_frame_ = own->second.header.frame_id;
    if (!given.empty() && !none && !info)
      throw Error(path_ + ": no messages on the camera-info topic " + given + " (--camera-info-topic)" +
                  topics_of_type(x, "sensor_msgs/msg/CameraInfo"));
    if (info && (config_camera.empty() || !given.empty() || set_.device_calibration)) {
      camera_ = camera_from_info(*info, PinholeCamera{}.bf, path_ + ": CameraInfo on " + set_.rgb_info);
      camera_source_ = "CameraInfo on " + set_.rgb_info;
      if (!config_camera.empty())
        spdlog::info(
            "{}: camera from the recording's CameraInfo ({}), not the config's dataset.camera {}; "
            "--camera-info-topic none uses dataset.camera",
            path_, set_.rgb_info, config_camera);
    } else if (!config_camera.empty()) {
      camera_file_ = io::load_camera_file(config_camera);
      camera_ = camera_file_.camera, camera_source_ = "dataset.camera " + config_camera;
      if (info && !info_matches(*info, camera_))
        spdlog::warn(
            "{}: the config's camera ({}x{}, fx {:.1f}) is not the recording's ({}: {}x{}, fx {:.1f})", path_,
            camera_.width, camera_.height, camera_.fx, set_.rgb_info, info->width, info->height, info->k[0]);
    } else {
      throw Error(path_ + ": no camera: no CameraInfo for the colour topic " + set_.rgb +
                  "; pass --camera-info-topic or set dataset.camera in the config" +
                  topics_of_type(x, "sensor_msgs/msg/CameraInfo"));
    }
    const cv::Mat first = colour(rgb_.msgs.front().ref);  // said now, not at frame 0 of the run
    if (first.cols != camera_.width || first.rows != camera_.height)
      throw Error(fmt::format("{}: the colour images are {}x{} but the camera ({}) is {}x{}", path_,
                              first.cols, first.rows, camera_source_, camera_.width, camera_.height));
  }

  // Raw depth: the depth camera and where /tf_static places it, for io::DepthToColour.
  void register_depth(const RecordingIndex& x, const std::string& config_camera) {
    registered_by_ = set_.registered_by;
    if (const auto& d = camera_file_.depth) {  // the config's camera file says depth is another camera's
      to_colour_ = std::make_shared<io::DepthToColour>(d->camera, camera_, d->T_c_d);
      registered_by_ = "s3m, with the depth_camera of dataset.camera " + config_camera;
    }
    if (to_colour_ || set_.registered()) return;
    const auto it = x.first_info.find(set_.depth_info);
    if (it == x.first_info.end())
      throw Error(path_ + ": no messages on " + set_.depth_info + " (the depth camera's intrinsics)");
    const CameraInfo& info = it->second;
    const auto rgb = x.first_info.find(set_.rgb_info);
    if (set_.registered_if_same_info && rgb != x.first_info.end() && info.k == rgb->second.k &&
        info.width == rgb->second.width && info.height == rgb->second.height) {
      registered_by_ = set_.recorder + " (depth_registration: the depth CameraInfo is the colour camera's)";
      return;
    }
    const std::string colour_frame = rgb == x.first_info.end() ? "" : rgb->second.header.frame_id;
    auto T_c_d = x.tf_static.lookup(colour_frame, info.header.frame_id);
    std::string by = "/tf_static";
    if (const auto e = x.first_extrinsics.find(set_.extrinsics); !T_c_d && e != x.first_extrinsics.end())
      T_c_d = e->second, by = set_.extrinsics;
    if (!T_c_d)
      throw Error(path_ + ": the depth (" + info.header.frame_id + ") is not registered to colour (" +
                  colour_frame +
                  ") and neither /tf_static nor an extrinsics topic connects them; record /tf_static, or the "
                  "driver's depth aligned to colour");
    to_colour_ = std::make_shared<io::DepthToColour>(
        camera_from_info(info, PinholeCamera{}.bf, path_ + ": " + set_.depth_info), camera_, *T_c_d);
    registered_by_ = "s3m, with the recording's depth camera and " + by;
    spdlog::info("{}: {}", path_, to_colour_->describe());
  }

  // PoseStamped: T_w_c as recorded. Odometry: the body's pose, moved onto the camera with /tf_static
  // when the tree connects the body frame to the colour camera's frame.
  void read_groundtruth(const RecordingIndex& x, const std::string& topic) {
    const auto it = x.poses.find(topic);
    if (topic.empty() || it == x.poses.end()) return;
    for (const PoseStamped& p : it->second) {
      SE3 T_w_c = p.T_frame_body;
      if (!p.child_frame_id.empty()) body_frame_ = p.child_frame_id;
      if (!p.child_frame_id.empty() && !camera_frame_.empty())
        if (const auto T_body_c = x.tf_static.lookup(p.child_frame_id, camera_frame_))
          T_w_c = T_w_c * *T_body_c;
      groundtruth_.push_back({p.header.stamp_s(), T_w_c});
    }
  }

  void find_robot(const RecordingIndex& x) {
    std::vector<std::string> frames = {"base_link", "base_footprint"};
    if (!body_frame_.empty()) frames.insert(frames.begin(), body_frame_);
    for (const std::string& f : frames)
      if (const auto T = camera_frame_.empty() ? std::nullopt : x.tf_static.lookup(camera_frame_, f)) {
        T_c_r_ = *T, robot_frame_ = f;
        return;
      }
  }

  void pair(double max_dt_s) {
    const auto stamps = [](const Stream& s) {
      std::vector<double> t;
      for (const auto& m : s.msgs) t.push_back(m.t_s);
      return t;
    };
    const io::StampPairs p = io::pair_by_stamp(stamps(rgb_), stamps(depth_), stamps(labels_), max_dt_s);
    for (const io::StampPair& q : p.pairs) pairs_.push_back({long(q.rgb), long(q.depth), q.labels});
    skipped_ = p.skipped;
    if (skipped_ > 0)
      spdlog::warn("{}: {} colour images without a depth image within {} s were skipped", path_, skipped_,
                   max_dt_s);
    if (pairs_.empty())
      throw Error(path_ + ": no colour/depth pairs within " + std::to_string(max_dt_s) + " s");
  }

  void describe(const RecordingIndex& x) {
    const auto topic = [&](const std::string& t) {
      const TopicStats& s = x.topics.at(t);
      return fmt::format("{} ({} messages, {:.1f} Hz)", t, s.messages, s.rate_hz());
    };
    layout_ = fmt::format("ROS 2 recording ({}), {}: colour {}, depth {} ({}){}; {} pairs{}", rec_.storage(),
                          set_.recorder, topic(set_.rgb), topic(set_.depth),
                          set_.registered() ? "registered to colour" : "aligned to colour here",
                          labels_.msgs.empty() ? "" : ", labels " + topic(set_.labels), pairs_.size(),
                          skipped_ ? fmt::format(", {} colour images without depth skipped", skipped_) : "");
    spdlog::info("{}: {}", path_, layout_);
  }

  cv::Mat aligned(const cv::Mat& depth_m, int index) const {
    const PinholeCamera& d = to_colour_->depth_camera();
    if (depth_m.cols != d.width || depth_m.rows != d.height)
      throw Error(fmt::format("{}: frame {} depth image is {}x{} (expected the depth camera's {}x{})", path_,
                              index, depth_m.cols, depth_m.rows, d.width, d.height));
    return (*to_colour_)(depth_m);
  }

  void check_size(const RgbdFrame& f) const {
    for (const cv::Mat* m : {&f.rgb, &f.depth_m, &f.labels})
      if (!m->empty() && (m->cols != camera_.width || m->rows != camera_.height))
        throw Error(fmt::format("{}: frame {} image is {}x{} (expected the camera's {}x{})", path_, f.index,
                                m->cols, m->rows, camera_.width, camera_.height));
  }

  std::string path_, layout_, camera_source_, registered_by_, camera_frame_, body_frame_, robot_frame_;
  std::optional<SE3> T_c_r_;
  Recording rec_;
  TopicSet set_;
  Stream rgb_, depth_, labels_;
  std::vector<Pair> pairs_;
  std::size_t skipped_ = 0;
  PinholeCamera camera_;
  io::CameraFile camera_file_;
  std::shared_ptr<const io::DepthToColour> to_colour_;  // raw depth; null = registered
  io::Trajectory groundtruth_;
};

}  // namespace

std::unique_ptr<Rosbag2Source> open_rosbag2_source(const std::string& path, const Rosbag2Topics& topics,
                                                   const pipeline::DatasetConfig& dataset) {
  return std::make_unique<Rosbag2FrameSource>(path, topics, dataset);
}

}  // namespace s3m::rosbag2
