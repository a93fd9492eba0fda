#include "bag_source.hpp"

#include <algorithm>
#include <cmath>
#include <map>
#include <string>
#include <vector>

#include <geometry_msgs/PoseStamped.h>
#include <rosbag/bag.h>
#include <rosbag/view.h>
#include <sensor_msgs/CameraInfo.h>
#include <sensor_msgs/Image.h>
#include <spdlog/spdlog.h>

#include "conversions.hpp"
#include "s3m/core/error.hpp"
#include "s3m/core/input_file.hpp"
#include "s3m/io/camera_yaml.hpp"

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
  for (const auto& [topic, n] : counts) list += (list.empty() ? "" : ", ") + topic + " (" + std::to_string(n) + ")";
  return "; its " + datatype + " topics (messages): " + list;
}

Stream image_index(const rosbag::Bag& bag, const std::string& path, const std::string& topic) {
  Stream out;
  for (const rosbag::MessageInstance& m : rosbag::View(bag, rosbag::TopicQuery(topic))) {
    out.by_time.push_back({to_seconds(instantiate<sensor_msgs::Image>(m, path)->header.stamp), out.msgs.size()});
    out.msgs.push_back(m);
  }
  std::stable_sort(out.by_time.begin(), out.by_time.end(),
                   [](const Stamped& a, const Stamped& b) { return a.t_s < b.t_s; });
  return out;
}

sensor_msgs::ImageConstPtr image_at(const Stream& s, std::size_t i, const std::string& path) {
  return instantiate<sensor_msgs::Image>(s.msgs[s.by_time[i].msg], path);
}

// Index of the entry of `v` (sorted) nearest to t within max_dt, or -1.
long nearest(const std::vector<Stamped>& v, double t, double max_dt) {
  auto it = std::lower_bound(v.begin(), v.end(), t, [](const Stamped& s, double x) { return s.t_s < x; });
  long best = -1;
  double best_dt = max_dt;
  for (auto c : {it, it == v.begin() ? v.end() : std::prev(it)}) {
    if (c == v.end()) continue;
    const double dt = std::abs(c->t_s - t);
    if (dt <= best_dt) best = c - v.begin(), best_dt = dt;
  }
  return best;
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
    rgb_ = image_index(bag_, path, topics.rgb);
    depth_ = image_index(bag_, path, topics.depth);
    const std::string images = "sensor_msgs/Image";
    if (rgb_.empty())
      throw Error(path + ": no messages on the colour topic " + topics.rgb + " (--rgb-topic)" + topics_of_type(bag_, images));
    if (depth_.empty())
      throw Error(path + ": no messages on the depth topic " + topics.depth + " (--depth-topic)" +
                  topics_of_type(bag_, images));
    if (!topics.labels.empty()) labels_ = image_index(bag_, path, topics.labels);
    camera_ = read_camera(topics.camera_info, dataset.camera);
    read_groundtruth(topics.groundtruth);
    pair(dataset.max_dt_s);
  }

  RgbdFrame load(std::size_t index) const override {
    require(index < pairs_.size(), path_ + ": frame " + std::to_string(index) + " requested, the bag has " +
                                       std::to_string(pairs_.size()) + " colour/depth pairs");
    const Pair& p = pairs_[index];
    RgbdFrame f;
    f.index = static_cast<int>(index);
    f.t_s = rgb_.by_time[p.rgb].t_s;
    f.rgb = colour_to_bgr(*image_at(rgb_, p.rgb, path_));
    f.depth_m = depth_to_metres(*image_at(depth_, p.depth, path_));
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

 private:
  struct Pair {
    long rgb, depth, labels;
  };

  PinholeCamera read_camera(const std::string& topic, const std::string& override_camera) const {
    if (!override_camera.empty()) return io::load_camera(override_camera);
    if (topic.empty()) throw Error(path_ + ": no camera: pass --camera-info-topic or set dataset.camera in the config");
    for (const rosbag::MessageInstance& m : rosbag::View(bag_, rosbag::TopicQuery(topic))) {
      const PinholeCamera defaults;
      return camera_from_info(*instantiate<sensor_msgs::CameraInfo>(m, path_), defaults.bf);
    }
    throw Error(path_ + ": no messages on the camera-info topic " + topic + " (--camera-info-topic, or \"\" and the "
                "config's dataset.camera)" + topics_of_type(bag_, "sensor_msgs/CameraInfo"));
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
    std::vector<bool> depth_used(depth_.msgs.size(), false);
    std::size_t skipped = 0;
    for (std::size_t i = 0; i < rgb_.by_time.size(); ++i) {
      const double t = rgb_.by_time[i].t_s;
      const long d = nearest(depth_.by_time, t, max_dt_s);
      if (d < 0 || depth_used[d]) {
        ++skipped;
        continue;
      }
      depth_used[d] = true;
      const long l = labels_.empty() ? -1 : nearest(labels_.by_time, t, max_dt_s);
      pairs_.push_back({static_cast<long>(i), d, l});
    }
    if (skipped > 0)
      spdlog::warn("{}: {} colour images without a depth image within {} s were skipped", path_, skipped, max_dt_s);
    if (pairs_.empty()) throw Error(path_ + ": no colour/depth pairs within " + std::to_string(max_dt_s) + " s");
  }

  void check_size(const RgbdFrame& f) const {
    for (const cv::Mat* m : {&f.rgb, &f.depth_m, &f.labels})
      if (!m->empty() && (m->cols != camera_.width || m->rows != camera_.height))
        throw Error(path_ + ": frame " + std::to_string(f.index) + " image is " + std::to_string(m->cols) + "x" +
                    std::to_string(m->rows) + " (expected the camera's " + std::to_string(camera_.width) + "x" +
                    std::to_string(camera_.height) + ")");
  }

  std::string path_;
  rosbag::Bag bag_;
  Stream rgb_, depth_, labels_;
  std::vector<Pair> pairs_;
  PinholeCamera camera_;
  io::Trajectory groundtruth_;
};

}  // namespace

std::unique_ptr<pipeline::FrameSource> open_bag_source(const std::string& bag_path, const BagTopics& topics,
                                                       const pipeline::DatasetConfig& dataset) {
  return std::make_unique<BagFrameSource>(bag_path, topics, dataset);
}

}  // namespace s3m::ros1
