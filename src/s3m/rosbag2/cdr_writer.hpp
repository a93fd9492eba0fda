#pragma once
// ROS 2 messages written in CDR (XCDR1 little endian), the inverse of cdr.hpp, for recordings s3m
// writes (`s3m tum2bag --format mcap|db3`).
#include <cstdint>
#include <cstring>
#include <string>
#include <vector>

#include <opencv2/core.hpp>

#include "s3m/core/camera.hpp"
#include "s3m/core/se3.hpp"

namespace s3m::rosbag2 {

class CdrWriter {
 public:
  CdrWriter() : b_{0x00, 0x01, 0x00, 0x00} {}
  void u8(std::uint8_t v) { b_.push_back(v); }
  void u32(std::uint32_t v) { put(v); }
  void i32(std::int32_t v) { put(v); }
  void f64(double v) { put(v); }
  void f32(float v) { put(v); }
  void str(const std::string& s);
  void bytes(const std::uint8_t* data, std::size_t n);  // uint8[]
  std::vector<std::uint8_t> take() { return std::move(b_); }

 private:
  template <typename T>
  void put(T v) {
    while ((b_.size() - 4) % sizeof(T)) b_.push_back(0);
    const std::size_t at = b_.size();
    b_.resize(at + sizeof(T));
    std::memcpy(b_.data() + at, &v, sizeof(T));
  }
  std::vector<std::uint8_t> b_;
};

// A std_msgs/Header's stamp from seconds: the nanoseconds of the decimal value, so that a stamp
// written from a text file's "1.033333" reads back as the double that text parses to.
struct Stamp {
  std::int32_t sec = 0;
  std::uint32_t nanosec = 0;
};
Stamp stamp_of(double t_s);

// sensor_msgs/msg/Image: CV_8UC3 BGR as rgb8, CV_32FC1 metres as 32FC1, CV_16UC1 as 16UC1.
std::vector<std::uint8_t> encode_image(Stamp t, const std::string& frame_id, const cv::Mat& image);
// sensor_msgs/msg/CameraInfo, plumb_bob.
std::vector<std::uint8_t> encode_camera_info(Stamp t, const std::string& frame_id,
                                             const PinholeCamera& camera);
// geometry_msgs/msg/PoseStamped: T_frame_body.
std::vector<std::uint8_t> encode_pose_stamped(Stamp t, const std::string& frame_id, const SE3& T_frame_body);
// tf2_msgs/msg/TFMessage with one transform T_parent_child.
std::vector<std::uint8_t> encode_tf_message(Stamp t, const std::string& parent, const std::string& child,
                                            const SE3& T_parent_child);

// Parts other encoders share: a std_msgs/Header, a geometry_msgs/Pose (T as position and orientation).
void write_header(CdrWriter& w, Stamp t, const std::string& frame_id);
void write_pose(CdrWriter& w, const SE3& T);

}  // namespace s3m::rosbag2
