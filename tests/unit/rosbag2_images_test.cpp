// Image messages to RgbdFrame images: encodings, row padding, and messages that disagree with
// their own sizes.
#include <gtest/gtest.h>

#include <opencv2/imgcodecs.hpp>

#include "io_test_util.hpp"
#include "s3m/rosbag2/images.hpp"

namespace s3m::rosbag2 {
namespace {

using s3m::testing::expect_error;

Image image(const std::string& encoding, std::uint32_t w, std::uint32_t h, std::uint32_t step,
            const std::vector<std::uint8_t>& data) {
  Image m;
  m.encoding = encoding, m.width = w, m.height = h, m.step = step;
  m.data = {data.data(), data.size()};
  return m;
}

TEST(Rosbag2Images, ColourEncodingsBecomeBgrAndRowPaddingIsSkipped) {
  const std::vector<std::uint8_t> rgb = {10, 20, 30, 40, 50, 60, 0, 0};  // 2x1 rgb8 with 2 pad bytes
  const cv::Mat a = colour_image(image("rgb8", 2, 1, 8, rgb), "m");
  ASSERT_EQ(a.type(), CV_8UC3);
  EXPECT_EQ(a.at<cv::Vec3b>(0, 0), cv::Vec3b(30, 20, 10));
  EXPECT_EQ(a.at<cv::Vec3b>(0, 1), cv::Vec3b(60, 50, 40));
  const std::vector<std::uint8_t> bgra = {1, 2, 3, 255};
  EXPECT_EQ(colour_image(image("bgra8", 1, 1, 4, bgra), "m").at<cv::Vec3b>(0, 0), cv::Vec3b(1, 2, 3));
  const std::vector<std::uint8_t> rgba = {1, 2, 3, 255};
  EXPECT_EQ(colour_image(image("rgba8", 1, 1, 4, rgba), "m").at<cv::Vec3b>(0, 0), cv::Vec3b(3, 2, 1));
  const std::vector<std::uint8_t> mono = {77};
  EXPECT_EQ(colour_image(image("mono8", 1, 1, 1, mono), "m").at<cv::Vec3b>(0, 0), cv::Vec3b(77, 77, 77));
}

TEST(Rosbag2Images, DepthIsMetres) {
  const std::vector<std::uint8_t> mm = {0xE8, 0x03, 0x00, 0x00};  // 1000 mm, 0 = none
  const cv::Mat d = depth_image(image("16UC1", 2, 1, 4, mm), 1e-3, "m");
  ASSERT_EQ(d.type(), CV_32FC1);
  EXPECT_EQ(d.at<float>(0, 0), 1.0f);
  EXPECT_EQ(d.at<float>(0, 1), 0.0f);
  const float z = 2.5f;
  std::vector<std::uint8_t> f(4);
  std::memcpy(f.data(), &z, 4);
  EXPECT_EQ(depth_image(image("32FC1", 1, 1, 4, f), 1e-3, "m").at<float>(0, 0), 2.5f);
}

TEST(Rosbag2Images, SizesThatDisagreeWithTheDataAreErrors) {
  const std::vector<std::uint8_t> six(6, 0);
  expect_error([&] { colour_image(image("rgb8", 2, 2, 6, six), "rec.db3: messages row 5 (/rgb)"); },
               {"rec.db3: messages row 5 (/rgb)", "2x2", "step 6", "6 data bytes", "expected"});
  expect_error([&] { colour_image(image("rgb8", 3, 1, 6, six), "m"); }, {"step >= 9"});
  expect_error([&] { colour_image(image("yuv422", 1, 1, 2, six), "m"); }, {"encoding 'yuv422'", "rgb8"});
  expect_error([&] { depth_image(image("8UC1", 6, 1, 6, six), 1e-3, "m"); }, {"depth encoding '8UC1'"});
  Image be = image("16UC1", 3, 1, 6, six);
  be.big_endian = true;
  expect_error([&] { depth_image(be, 1e-3, "m"); }, {"big-endian"});
}

TEST(Rosbag2Images, CompressedColourAndImageTransportCompressedDepth) {
  cv::Mat bgr(2, 3, CV_8UC3, cv::Scalar(5, 6, 7));
  std::vector<std::uint8_t> png;
  cv::imencode(".png", bgr, png);
  CompressedImage c;
  c.format = "png";
  c.data = {png.data(), png.size()};
  const cv::Mat back = colour_image(c, "m");
  EXPECT_EQ(cv::norm(back, bgr, cv::NORM_INF), 0.0);

  // compressedDepth 16UC1: 12-byte ConfigHeader (format, depthQuantA, depthQuantB), then 16-bit PNG.
  cv::Mat mm(1, 2, CV_16UC1);
  mm.at<std::uint16_t>(0, 0) = 1500, mm.at<std::uint16_t>(0, 1) = 0;
  std::vector<std::uint8_t> raw;
  cv::imencode(".png", mm, raw);
  std::vector<std::uint8_t> msg(12, 0);
  msg.insert(msg.end(), raw.begin(), raw.end());
  c.format = "16UC1; compressedDepth png";
  c.data = {msg.data(), msg.size()};
  const cv::Mat d = depth_image(c, 1e-3, "m");
  EXPECT_FLOAT_EQ(d.at<float>(0, 0), 1.5f);
  EXPECT_EQ(d.at<float>(0, 1), 0.0f);

  // 32FC1: inverse depth, q = A / z + B; z = 2 m with A = 1000, B = 10 is q = 510.
  cv::Mat q(1, 1, CV_16UC1, cv::Scalar(510));
  cv::imencode(".png", q, raw);
  const float A = 1000.0f, B = 10.0f;
  std::vector<std::uint8_t> inv(12, 0);
  std::memcpy(inv.data() + 4, &A, 4), std::memcpy(inv.data() + 8, &B, 4);
  inv.insert(inv.end(), raw.begin(), raw.end());
  c.format = "32FC1; compressedDepth png";
  c.data = {inv.data(), inv.size()};
  EXPECT_FLOAT_EQ(depth_image(c, 1e-3, "m").at<float>(0, 0), 2.0f);

  c.format = "jpeg";
  const std::vector<std::uint8_t> junk = {1, 2, 3};
  c.data = {junk.data(), junk.size()};
  expect_error([&] { colour_image(c, "m"); }, {"does not decode"});
  c.format = "16UC1; compressedDepth png";
  expect_error([&] { depth_image(c, 1e-3, "m"); }, {"compressedDepth header"});
}

}  // namespace
}  // namespace s3m::rosbag2
