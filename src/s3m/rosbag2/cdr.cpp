#include "s3m/rosbag2/cdr.hpp"

#include <cmath>
#include <cstdlib>

#include <fmt/format.h>

namespace s3m::rosbag2 {

CdrReader::CdrReader(Bytes b, const std::string& where) : r_(b, where) {
  const Bytes head = r_.take(4, "CDR encapsulation header");
  if (head.data[0] != 0 || head.data[1] != 1)
    throw Error(where + ": CDR encapsulation " + std::to_string(head.data[0]) + " " +
                std::to_string(head.data[1]) + " (expected 0 1: plain CDR, little endian)");
}

std::string CdrReader::str(const char* field) {
  const std::uint32_t n = u32(field);
  if (n == 0) return "";  // some writers leave out the NUL of an empty string
  std::string s = r_.text(n, field);
  if (s.back() != '\0')
    throw Error(r_.where() + ": " + field + " string does not end in NUL (corrupt message)");
  s.pop_back();
  return s;
}

std::uint32_t CdrReader::count(const char* field, std::size_t element_size) {
  const std::uint32_t n = u32(field);
  r_.need(static_cast<std::size_t>(n) * element_size, field);  // before any allocation of n elements
  return n;
}

Bytes CdrReader::bytes(const char* field) { return r_.take(count(field, 1), field); }

double Header::stamp_s() const {
  if (sec < 0) return sec + nanosec * 1e-9;  // before 1970: no text file to agree with
  const std::string s = fmt::format("{}.{:09d}", sec, nanosec);
  return std::strtod(s.c_str(), nullptr);
}

Header read_header(CdrReader& r) {
  Header h;
  h.sec = r.i32("header.stamp.sec");
  h.nanosec = r.u32("header.stamp.nanosec");
  h.frame_id = r.str("header.frame_id");
  return h;
}

namespace {

Vec3 read_vec3(CdrReader& r, const char* field) {
  const double x = r.f64(field), y = r.f64(field), z = r.f64(field);
  return {x, y, z};
}

SE3 read_pose(CdrReader& r, const char* position, const char* orientation) {
  const Vec3 t = read_vec3(r, position);
  const double x = r.f64(orientation), y = r.f64(orientation), z = r.f64(orientation), w = r.f64(orientation);
  if (!(x * x + y * y + z * z + w * w > 0.5))  // also refuses NaN; tf2 also needs a unit quaternion
    throw Error(std::string(orientation) + " is not a unit quaternion");
  return make_se3(t, Quat(w, x, y, z));
}

template <typename F>
auto with_where(const std::string& where, F f) {
  try {
    return f();
  } catch (const Error& e) {
    const std::string what = e.what();
    throw Error(what.compare(0, where.size(), where) == 0 ? what : where + ": " + what);
  }
}

}  // namespace

Image decode_image(Bytes b, const std::string& where) {
  CdrReader r(b, where);
  Image m;
  m.header = read_header(r);
  m.height = r.u32("height");
  m.width = r.u32("width");
  m.encoding = r.str("encoding");
  m.big_endian = r.u8("is_bigendian") != 0;
  m.step = r.u32("step");
  m.data = r.bytes("data");
  return m;
}

CompressedImage decode_compressed_image(Bytes b, const std::string& where) {
  CdrReader r(b, where);
  CompressedImage m;
  m.header = read_header(r);
  m.format = r.str("format");
  m.data = r.bytes("data");
  return m;
}

CameraInfo decode_camera_info(Bytes b, const std::string& where) {
  CdrReader r(b, where);
  CameraInfo m;
  m.header = read_header(r);
  m.height = r.u32("height");
  m.width = r.u32("width");
  m.distortion_model = r.str("distortion_model");
  m.d.resize(r.count("d", 8));
  for (double& x : m.d) x = r.f64("d");
  for (double& x : m.k) x = r.f64("k");
  for (int i = 0; i < 9; ++i) r.f64("r");
  for (double& x : m.p) x = r.f64("p");
  return m;  // binning and roi follow; s3m uses neither
}

std::vector<TransformStamped> decode_tf_message(Bytes b, const std::string& where) {
  return with_where(where, [&] {
    CdrReader r(b, where);
    std::vector<TransformStamped> out(r.count("transforms", 4 + 4 + 4 + 4 + 56));
    for (TransformStamped& t : out) {
      t.header = read_header(r);
      t.child_frame_id = r.str("child_frame_id");
      t.T_parent_child = read_pose(r, "transform.translation", "transform.rotation");
    }
    return out;
  });
}

PoseStamped decode_pose_stamped(Bytes b, const std::string& where) {
  return with_where(where, [&] {
    CdrReader r(b, where);
    PoseStamped m;
    m.header = read_header(r);
    m.T_frame_body = read_pose(r, "pose.position", "pose.orientation");
    return m;
  });
}

PoseStamped decode_odometry(Bytes b, const std::string& where) {
  return with_where(where, [&] {
    CdrReader r(b, where);
    PoseStamped m;
    m.header = read_header(r);
    m.child_frame_id = r.str("child_frame_id");
    m.T_frame_body = read_pose(r, "pose.pose.position", "pose.pose.orientation");
    return m;
  });
}

SE3 decode_extrinsics(Bytes b, const std::string& where) {
  CdrReader r(b, where);
  Mat3 R;
  for (int c = 0; c < 3; ++c)
    for (int row = 0; row < 3; ++row) R(row, c) = r.f64("rotation");
  Vec3 t;
  for (int i = 0; i < 3; ++i) t(i) = r.f64("translation");
  if (!R.allFinite() || !t.allFinite() || std::abs(R.determinant() - 1.0) > 1e-3)
    throw Error(where +
                ": rotation is not a rotation matrix (expected realsense2_camera's column-major 3x3)");
  return make_se3(R, t);
}

}  // namespace s3m::rosbag2
