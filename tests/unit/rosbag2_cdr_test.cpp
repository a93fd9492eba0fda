// The XCDR1 decoder on bytes worked out by hand from the ROS 2 message definitions and the CDR
// alignment rules (each primitive aligned to its size, counted after the 4-byte encapsulation).
#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <cstring>
#include <vector>

#include "io_test_util.hpp"
#include "s3m/rosbag2/cdr.hpp"

namespace s3m::rosbag2 {
namespace {

using s3m::testing::expect_error;
using Buf = std::vector<std::uint8_t>;

// Little-endian field writers for building messages by hand, each aligned as CDR aligns it.
void pad(Buf& b, std::size_t align) {  // offsets count from after the 4-byte encapsulation header
  while ((b.size() - 4) % align) b.push_back(0);
}
void u32(Buf& b, std::uint32_t v) {
  pad(b, 4);
  for (int i = 0; i < 4; ++i) b.push_back(static_cast<std::uint8_t>(v >> (8 * i)));
}
void f64(Buf& b, double v) {
  pad(b, 8);
  std::uint64_t x;
  std::memcpy(&x, &v, 8);
  for (int i = 0; i < 8; ++i) b.push_back(static_cast<std::uint8_t>(x >> (8 * i)));
}
void str(Buf& b, const std::string& s) {
  u32(b, static_cast<std::uint32_t>(s.size() + 1));
  b.insert(b.end(), s.begin(), s.end());
  b.push_back(0);
}
Buf header(std::int32_t sec, std::uint32_t nsec, const std::string& frame) {
  Buf b = {0x00, 0x01, 0x00, 0x00};  // CDR_LE
  u32(b, static_cast<std::uint32_t>(sec));
  u32(b, nsec);
  str(b, frame);
  return b;
}
Bytes view(const Buf& b) { return {b.data(), b.size()}; }

TEST(Rosbag2Cdr, ImageFromHandWrittenBytes) {
  // Image{stamp 1 s 2 ns, frame "cam", 1x2 mono8, step 2, data 07 09}: "mono8\0" ends at offset 34,
  // is_bigendian takes 34, one pad byte, step at 36.
  const Buf b = {0x00, 0x01, 0x00, 0x00, 0x01, 0x00, 0x00, 0x00, 0x02, 0x00, 0x00, 0x00, 0x04,
                 0x00, 0x00, 0x00, 'c',  'a',  'm',  0x00, 0x01, 0x00, 0x00, 0x00, 0x02, 0x00,
                 0x00, 0x00, 0x06, 0x00, 0x00, 0x00, 'm',  'o',  'n',  'o',  '8',  0x00, 0x00,
                 0x00, 0x02, 0x00, 0x00, 0x00, 0x02, 0x00, 0x00, 0x00, 0x07, 0x09};
  const Image m = decode_image(view(b), "img");
  EXPECT_EQ(m.header.sec, 1);
  EXPECT_EQ(m.header.nanosec, 2u);
  EXPECT_EQ(m.header.frame_id, "cam");
  EXPECT_EQ(m.height, 1u);
  EXPECT_EQ(m.width, 2u);
  EXPECT_EQ(m.encoding, "mono8");
  EXPECT_FALSE(m.big_endian);
  EXPECT_EQ(m.step, 2u);
  ASSERT_EQ(m.data.size, 2u);
  EXPECT_EQ(m.data.data[0], 7);
  EXPECT_EQ(m.data.data[1], 9);
}

TEST(Rosbag2Cdr, CameraInfoAlignsDoublesToEightBytes) {
  Buf b = header(10, 500000000, "c");  // "c\0" ends at offset 14 (after the encapsulation)
  u32(b, 480);                         // at 16, after 2 pad bytes
  u32(b, 640);
  str(b, "plumb_bob");  // length at 24, text to 38
  u32(b, 5);            // d count at 40; d[0] at 48 after 4 pad bytes
  EXPECT_EQ(b.size() - 4, 44u);
  for (double d : {0.1, -0.2, 0.001, 0.002, 0.05}) f64(b, d);
  for (double k : {500.0, 0.0, 320.0, 0.0, 501.0, 240.0, 0.0, 0.0, 1.0}) f64(b, k);
  for (int i = 0; i < 9; ++i) f64(b, i % 4 == 0 ? 1.0 : 0.0);
  for (int i = 0; i < 12; ++i) f64(b, i == 3 ? -25.0 : 1.0);
  for (int i = 0; i < 6; ++i) u32(b, 0);  // binning, roi
  b.push_back(0);
  const CameraInfo c = decode_camera_info(view(b), "info");
  EXPECT_EQ(c.width, 640u);
  EXPECT_EQ(c.distortion_model, "plumb_bob");
  ASSERT_EQ(c.d.size(), 5u);
  EXPECT_EQ(c.d[1], -0.2);
  EXPECT_EQ(c.k[0], 500.0);
  EXPECT_EQ(c.k[5], 240.0);
  EXPECT_EQ(c.p[3], -25.0);
  EXPECT_EQ(c.header.stamp_s(), 10.5);
}

TEST(Rosbag2Cdr, StampIsTheNearestDoubleToTheDecimalTime) {
  Header h;
  h.sec = 1305031102, h.nanosec = 175304000;
  EXPECT_EQ(h.stamp_s(), 1305031102.175304);  // what "1305031102.175304" in a TUM list parses to
  h.sec = 1, h.nanosec = 33333000;
  EXPECT_EQ(h.stamp_s(), 1.033333);
}

TEST(Rosbag2Cdr, TfMessageAndOdometryPoses) {
  Buf tf = {0x00, 0x01, 0x00, 0x00};
  u32(tf, 1);
  Buf h = header(3, 0, "base_link");
  tf.insert(tf.end(), h.begin() + 4, h.end());
  str(tf, "camera");
  for (double v : {0.1, 0.2, 0.3}) f64(tf, v);
  for (double v : {0.0, 0.0, std::sqrt(0.5), std::sqrt(0.5)}) f64(tf, v);  // 90 deg about z
  const auto t = decode_tf_message(view(tf), "tf");
  ASSERT_EQ(t.size(), 1u);
  EXPECT_EQ(t[0].header.frame_id, "base_link");
  EXPECT_EQ(t[0].child_frame_id, "camera");
  const Vec3 p = t[0].T_parent_child * Vec3(1, 0, 0);
  EXPECT_NEAR(p.x(), 0.1, 1e-12);
  EXPECT_NEAR(p.y(), 1.2, 1e-12);
  EXPECT_NEAR(p.z(), 0.3, 1e-12);

  Buf odom = header(4, 0, "odom");
  str(odom, "base_link");
  for (double v : {1.0, 2.0, 3.0, 0.0, 0.0, 0.0, 1.0}) f64(odom, v);
  for (int i = 0; i < 36 + 6 + 36; ++i) f64(odom, 0.0);
  const PoseStamped o = decode_odometry(view(odom), "odom");
  EXPECT_EQ(o.child_frame_id, "base_link");
  EXPECT_EQ(o.T_frame_body.translation(), Vec3(1, 2, 3));
}

TEST(Rosbag2Cdr, RealsenseExtrinsicsAreColumnMajor) {
  Buf b = {0x00, 0x01, 0x00, 0x00};
  for (double v : {0.0, 1.0, 0.0, -1.0, 0.0, 0.0, 0.0, 0.0, 1.0}) f64(b, v);  // columns: 90 deg about z
  for (double v : {0.015, 0.0, 0.0}) f64(b, v);
  const SE3 T = decode_extrinsics(view(b), "ext");
  const Vec3 p = T * Vec3(1, 0, 0);  // x -> y, then the translation
  EXPECT_NEAR(p.x(), 0.015, 1e-15);
  EXPECT_NEAR(p.y(), 1.0, 1e-15);
  b.resize(b.size() - 8);
  expect_error([&] { decode_extrinsics(view(b), "ext"); }, {"ext", "translation", "truncated"});
}

TEST(Rosbag2Cdr, TruncatedOrForeignBytesAreErrorsNamingTheField) {
  Buf b = header(1, 0, "cam");
  u32(b, 480);
  expect_error([&] { decode_image(view(b), "rec.mcap: message at byte 99"); },
               {"rec.mcap: message at byte 99", "width", "truncated"});
  Buf big = b;
  big[1] = 0x00;  // CDR_BE
  expect_error([&] { decode_image(view(big), "m"); }, {"encapsulation", "little endian"});
  Buf huge = header(1, 0, "cam");
  u32(huge, 0xFFFFFFF0u);  // a d count no message holds: refused before any allocation
  expect_error([&] { decode_compressed_image(view(huge), "m"); }, {"m:", "format"});
  Buf quat = header(1, 0, "w");
  for (int i = 0; i < 7; ++i) f64(quat, 0.0);  // all-zero quaternion
  expect_error([&] { decode_pose_stamped(view(quat), "gt"); }, {"gt", "unit quaternion"});
}

}  // namespace
}  // namespace s3m::rosbag2
