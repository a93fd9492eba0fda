#include "bag_writer.hpp"

#include <algorithm>

#include <geometry_msgs/PoseStamped.h>
#include <rosbag/bag.h>

#include "conversions.hpp"
#include "s3m/core/error.hpp"
#include "s3m/io/tum_dataset.hpp"

namespace s3m::ros1 {

std::size_t write_tum_to_bag(const std::string& dataset_dir, const std::string& bag_path,
                             const BagWriteOptions& o) {
  const io::TumDataset ds = io::TumDataset::open(dataset_dir);
  rosbag::Bag bag;
  try {
    bag.open(bag_path, rosbag::bagmode::Write);
  } catch (const rosbag::BagException& e) {
    throw Error("tum2bag: cannot write " + bag_path + ": " + e.what());
  }
  sensor_msgs::CameraInfo info = info_from_camera(ds.camera());
  std::size_t n = ds.size();
  if (o.max_frames >= 0) n = std::min<std::size_t>(n, o.max_frames);
  for (std::size_t i = 0; i < n; ++i) {
    const RgbdFrame f = ds.load(i);
    std_msgs::Header h;
    h.seq = static_cast<std::uint32_t>(i);
    h.stamp = to_ros_time(f.t_s);
    h.frame_id = o.camera_frame;
    sensor_msgs::Image rgb = bgr_to_msg(f.rgb), depth = depth_to_msg(f.depth_m, o.depth_encoding);
    rgb.header = depth.header = info.header = h;
    bag.write(o.topics.rgb, h.stamp, rgb);
    bag.write(o.topics.depth, h.stamp, depth);
    if (!o.topics.camera_info.empty()) bag.write(o.topics.camera_info, h.stamp, info);
    if (!o.topics.labels.empty() && !f.labels.empty()) {
      sensor_msgs::Image labels = labels_to_msg(f.labels);
      labels.header = h;
      bag.write(o.topics.labels, h.stamp, labels);
    }
  }
  if (!o.topics.groundtruth.empty()) {
    for (const StampedPose& p : ds.groundtruth()) {
      geometry_msgs::PoseStamped m;
      m.header.stamp = to_ros_time(p.t_s);
      m.header.frame_id = o.world_frame;
      m.pose = to_pose(p.T_w_x);
      bag.write(o.topics.groundtruth, m.header.stamp, m);
    }
  }
  bag.close();
  return n;
}

}  // namespace s3m::ros1
