// Fuzz targets for ROS 2 recordings: an MCAP file (records, chunks in every compression, CRCs) with
// every message on a known type decoded and turned into images as a frame source would, and a
// single CDR message of the type its first byte selects.
#include <string>

#include "fuzz/targets.hpp"
#include "fuzz/targets_list.hpp"
#include "s3m/rosbag2/camera_info.hpp"
#include "s3m/rosbag2/images.hpp"
#include "s3m/rosbag2/storage.hpp"

namespace s3m::fuzz {
namespace {

using rosbag2::Bytes;

// Everything s3m does with a message of `type` that it reads.
void decode(const std::string& type, Bytes b) {
  const std::string where = "fuzz";
  if (type == "sensor_msgs/msg/Image") {
    const rosbag2::Image m = rosbag2::decode_image(b, where);
    expect_clean([&] { rosbag2::colour_image(m, where); });
    expect_clean([&] { rosbag2::depth_image(m, 1e-3, where); });
    expect_clean([&] { rosbag2::label_image(m, where); });
  } else if (type == "sensor_msgs/msg/CompressedImage") {
    const rosbag2::CompressedImage m = rosbag2::decode_compressed_image(b, where);
    expect_clean([&] { rosbag2::colour_image(m, where); });
    expect_clean([&] { rosbag2::depth_image(m, 1e-3, where); });
  } else if (type == "sensor_msgs/msg/CameraInfo") {
    rosbag2::camera_from_info(rosbag2::decode_camera_info(b, where), 40.0, where);
  } else if (type == "tf2_msgs/msg/TFMessage") {
    rosbag2::decode_tf_message(b, where);
  } else if (type == "geometry_msgs/msg/PoseStamped") {
    rosbag2::decode_pose_stamped(b, where);
  } else if (type == "nav_msgs/msg/Odometry") {
    rosbag2::decode_odometry(b, where);
  }
}

void fuzz_mcap(const std::uint8_t* data, std::size_t size) {
  const std::string path = write_scratch("recording.mcap", data, size);
  expect_clean([&] {
    const auto file = rosbag2::open_mcap(path);
    std::vector<std::pair<std::string, rosbag2::MessageRef>> refs;
    file->scan([&](const rosbag2::MessageView& m) {
      expect_clean([&] { decode(m.channel->type, m.data); });
      if (refs.size() < 64) refs.emplace_back(m.channel->type, m.ref);
    });
    for (const auto& [type, ref] : refs) {  // read again as a frame source does, chunk by chunk
      const std::vector<std::uint8_t> again = file->read(ref);
      expect_clean([&] { decode(type, {again.data(), again.size()}); });
    }
  });
}

// First byte: which type; the rest: the CDR message (with its encapsulation header).
void fuzz_cdr(const std::uint8_t* data, std::size_t size) {
  static const char* types[] = {"sensor_msgs/msg/Image",         "sensor_msgs/msg/CompressedImage",
                                "sensor_msgs/msg/CameraInfo",    "tf2_msgs/msg/TFMessage",
                                "geometry_msgs/msg/PoseStamped", "nav_msgs/msg/Odometry"};
  if (size == 0) return;
  // A copy of exactly the message's bytes, so a read past its end is the sanitizer's to see.
  const std::vector<std::uint8_t> message(data + 1, data + size);
  expect_clean([&] { decode(types[data[0] % 6], {message.data(), message.size()}); });
}

}  // namespace

void append_rosbag2_targets(std::vector<Target>& out) {
  out.push_back({"mcap", fuzz_mcap});
  out.push_back({"cdr", fuzz_cdr});
}

}  // namespace s3m::fuzz
