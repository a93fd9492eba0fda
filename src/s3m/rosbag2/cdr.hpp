#pragma once
// ROS 2 messages in CDR (XCDR1, the rmw default): a 4-byte encapsulation header (00 01 = little
// endian; big endian is refused), then the fields in order, each primitive aligned to its own size
// counted from the end of that header; strings as uint32 length (with the NUL) + bytes + NUL;
// sequences as uint32 count + elements. Only the types s3m reads are decoded.
// Units: times in seconds, lengths in metres; poses named as in s3m/core/se3.hpp.
#include <array>
#include <cstdint>
#include <string>
#include <vector>

#include "s3m/core/se3.hpp"
#include "s3m/rosbag2/bytes.hpp"

namespace s3m::rosbag2 {

class CdrReader {
 public:
  // where: names the message in errors. Throws s3m::Error on a bad encapsulation header.
  CdrReader(Bytes b, const std::string& where);
  std::uint8_t u8(const char* field) { return r_.le<std::uint8_t>(field); }
  std::uint32_t u32(const char* field) { return aligned<std::uint32_t>(field); }
  std::int32_t i32(const char* field) { return aligned<std::int32_t>(field); }
  double f64(const char* field) { return aligned<double>(field); }
  std::string str(const char* field);
  Bytes bytes(const char* field);                                    // uint8[]: a view into the message
  std::uint32_t count(const char* field, std::size_t element_size);  // a sequence's length, checked
  std::size_t left() const { return r_.left(); }

 private:
  template <typename T>
  T aligned(const char* field) {
    const std::size_t pad = (sizeof(T) - (r_.pos() - 4) % sizeof(T)) % sizeof(T);
    r_.skip(pad, field);
    return r_.le<T>(field);
  }
  ByteReader r_;
};

struct Header {
  std::int32_t sec = 0;
  std::uint32_t nanosec = 0;
  std::string frame_id;
  // sec.nanosec as the double nearest to that decimal number: the same double a text file with
  // that stamp parses to (TUM's rgb.txt), so a recording made from a dataset times frames identically.
  double stamp_s() const;
};

struct Image {  // sensor_msgs/msg/Image
  Header header;
  std::uint32_t height = 0, width = 0, step = 0;  // step: bytes per row
  std::string encoding;                           // "rgb8", "16UC1", ...
  bool big_endian = false;
  Bytes data;
};

struct CompressedImage {  // sensor_msgs/msg/CompressedImage
  Header header;
  std::string format;  // "jpeg", "png", "bgr8; jpeg compressed bgr8", "16UC1; compressedDepth png"
  Bytes data;
};

struct CameraInfo {  // sensor_msgs/msg/CameraInfo
  Header header;
  std::uint32_t height = 0, width = 0;
  std::string distortion_model;  // "plumb_bob", "rational_polynomial", ...
  std::vector<double> d;
  std::array<double, 9> k{};   // row-major intrinsics [px]
  std::array<double, 12> p{};  // row-major projection; p[3] = -fx * baseline for a right stereo camera
};

struct TransformStamped {  // geometry_msgs/msg/TransformStamped
  Header header;           // header.frame_id: the parent frame
  std::string child_frame_id;
  SE3 T_parent_child;
};

struct PoseStamped {  // geometry_msgs/msg/PoseStamped, or the pose of a nav_msgs/msg/Odometry
  Header header;
  std::string child_frame_id;  // Odometry: the body frame; "" for a PoseStamped
  SE3 T_frame_body;            // maps body points into header.frame_id
};

// Each throws s3m::Error naming `where` and the field when the message is shorter than its fields.
Header read_header(CdrReader& r);  // a message's leading std_msgs/Header, e.g. for its stamp alone
Image decode_image(Bytes b, const std::string& where);
CompressedImage decode_compressed_image(Bytes b, const std::string& where);
CameraInfo decode_camera_info(Bytes b, const std::string& where);
std::vector<TransformStamped> decode_tf_message(Bytes b, const std::string& where);  // tf2_msgs/msg/TFMessage
PoseStamped decode_pose_stamped(Bytes b, const std::string& where);
// realsense2_camera_msgs/msg/Extrinsics (float64[9] rotation, column-major as librealsense's
// rs2_extrinsics; float64[3] translation [m]): T_to_from, e.g. T_colour_depth for depth_to_color.
SE3 decode_extrinsics(Bytes b, const std::string& where);
PoseStamped decode_odometry(Bytes b, const std::string& where);  // its pose (the twist is left)

}  // namespace s3m::rosbag2
