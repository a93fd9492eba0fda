#include "s3m/rosbag2/dataset_writer.hpp"

#include <cmath>

#include "s3m/core/error.hpp"
#include "s3m/rosbag2/cdr_writer.hpp"
#include "s3m/rosbag2/writer.hpp"

namespace s3m::rosbag2 {

void DatasetWriteOptions::validate() const {
  require(format == "mcap" || format == "db3",
          "ROS 2 recording format '" + format + "' (expected mcap or db3)");
  require(compression == "zstd" || compression == "none",
          "MCAP chunk compression '" + compression + "' (expected zstd or none)");
  require(!rgb_topic.empty() && !depth_topic.empty() && !camera_info_topic.empty(),
          "ROS 2 recording: the colour, depth and camera-info topics must be named");
}

namespace {

std::int64_t nanoseconds(Stamp t) { return static_cast<std::int64_t>(t.sec) * 1000000000 + t.nanosec; }

}  // namespace

std::size_t write_dataset(const io::Dataset& dataset, const std::string& path, const DatasetWriteOptions& o) {
  o.validate();
  auto w = o.format == "mcap" ? create_mcap(path, o.compression == "zstd" ? "zstd" : "") : create_db3(path);
  const int rgb = w->add_topic(o.rgb_topic, "sensor_msgs/msg/Image"),
            depth = w->add_topic(o.depth_topic, "sensor_msgs/msg/Image"),
            info = w->add_topic(o.camera_info_topic, "sensor_msgs/msg/CameraInfo");
  const bool labels = dataset.has_labels() && !o.labels_topic.empty();
  const int label = labels ? w->add_topic(o.labels_topic, "sensor_msgs/msg/Image") : 0;
  const std::size_t n = o.max_frames < 0
                            ? dataset.size()
                            : std::min<std::size_t>(dataset.size(), static_cast<std::size_t>(o.max_frames));
  if (n == 0) throw Error(dataset.dir() + ": no frames to write");
  const Stamp first = stamp_of(dataset.timestamp(0));
  if (o.T_c_r) {
    const int tf = w->add_topic("/tf_static", "tf2_msgs/msg/TFMessage");
    w->write(tf, nanoseconds(first), encode_tf_message(first, "base_link", o.frame_id, o.T_c_r->inverse()));
  }
  for (std::size_t i = 0; i < n; ++i) {
    const RgbdFrame f = dataset.load(i);
    const Stamp tc = stamp_of(dataset.entries()[i].t_rgb_s), td = stamp_of(dataset.entries()[i].t_depth_s);
    w->write(info, nanoseconds(tc), encode_camera_info(tc, o.frame_id, dataset.camera()));
    w->write(rgb, nanoseconds(tc), encode_image(tc, o.frame_id, f.rgb));
    w->write(depth, nanoseconds(td), encode_image(td, o.frame_id, f.depth_m));
    if (labels && !f.labels.empty()) w->write(label, nanoseconds(tc), encode_image(tc, o.frame_id, f.labels));
  }
  if (!o.gt_topic.empty() && !dataset.groundtruth().empty()) {
    const int gt = w->add_topic(o.gt_topic, "geometry_msgs/msg/PoseStamped");
    for (const StampedPose& p : dataset.groundtruth()) {
      const Stamp t = stamp_of(p.t_s);
      w->write(gt, nanoseconds(t), encode_pose_stamped(t, "world", p.T_w_x));
    }
  }
  w->close();
  return n;
}

}  // namespace s3m::rosbag2
