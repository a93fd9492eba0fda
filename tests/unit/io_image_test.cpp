#include <gtest/gtest.h>

#include <cmath>
#include <opencv2/imgcodecs.hpp>

#include "io_test_util.hpp"
#include "s3m/io/image_io.hpp"

using namespace s3m;
using namespace s3m::io;
using s3m::testing::expect_error;
using s3m::testing::fresh_temp_dir;

TEST(IoImage, DepthRoundTripRoundsClampsAndZeroesInvalid) {
  const auto dir = fresh_temp_dir();
  cv::Mat d(2, 4, CV_32F);
  d.at<float>(0, 0) = 1.0f;          // 5000
  d.at<float>(0, 1) = 0.00011f;      // 0.55 -> 1
  d.at<float>(0, 2) = 20.0f;         // 100000 -> clamp 65535
  d.at<float>(0, 3) = NAN;           // -> 0
  d.at<float>(1, 0) = -1.0f;         // -> 0
  d.at<float>(1, 1) = INFINITY;      // -> 0
  d.at<float>(1, 2) = 0.0f;          // -> 0
  d.at<float>(1, 3) = 2.50016f;      // 12500.8 -> 12501
  const auto path = (dir / "d.png").string();
  write_depth_png(path, d, 5000.0);
  const cv::Mat raw = cv::imread(path, cv::IMREAD_UNCHANGED);
  ASSERT_EQ(raw.type(), CV_16UC1);
  const std::uint16_t expected[8] = {5000, 1, 65535, 0, 0, 0, 0, 12501};
  for (int i = 0; i < 8; ++i) EXPECT_EQ(raw.at<std::uint16_t>(i / 4, i % 4), expected[i]) << i;
  const cv::Mat back = read_depth_png(path, 5000.0, {4, 2});
  ASSERT_EQ(back.type(), CV_32FC1);
  EXPECT_FLOAT_EQ(back.at<float>(0, 0), 1.0f);
  EXPECT_FLOAT_EQ(back.at<float>(0, 2), 65535.0f / 5000.0f);
  EXPECT_FLOAT_EQ(back.at<float>(1, 3), 12501.0f / 5000.0f);
  EXPECT_EQ(back.at<float>(0, 3), 0.0f);
}

TEST(IoImage, DepthErrors) {
  const auto dir = fresh_temp_dir();
  const auto p8 = (dir / "d8.png").string();
  cv::imwrite(p8, cv::Mat(3, 3, CV_8UC1, cv::Scalar(7)));
  expect_error([&] { read_depth_png(p8, 5000); }, {"d8.png", "8-bit unsigned 1-channel 3x3", "16-bit single-channel depth PNG"});
  const auto p16 = (dir / "d16.png").string();
  cv::imwrite(p16, cv::Mat(3, 4, CV_16UC1, cv::Scalar(7)));
  expect_error([&] { read_depth_png(p16, 5000, {640, 480}); }, {"d16.png", "image is 4x3", "640x480"});
  expect_error([&] { read_depth_png((dir / "none.png").string(), 5000); }, {"none.png", "not found"});
  s3m::testing::write_file(dir / "junk.png", "this is not a png");
  expect_error([&] { read_depth_png((dir / "junk.png").string(), 5000); },
               {"junk.png", "not a PNG or JPEG file (it starts with bytes 74 68 69 73 20 69 73 20)"});
  s3m::testing::write_file(dir / "empty.png", "");
  expect_error([&] { read_depth_png((dir / "empty.png").string(), 5000); }, {"empty.png", "file is empty"});
  // A real PNG signature with a broken body still goes to the PNG decoder, which reports it.
  s3m::testing::write_file(dir / "cut.png", std::string("\x89PNG\r\n\x1a\n\0\0", 10));
  expect_error([&] { read_depth_png((dir / "cut.png").string(), 5000); }, {"cut.png", "cannot read or decode"});
  expect_error([&] { write_depth_png((dir / "x.png").string(), cv::Mat(2, 2, CV_16UC1), 5000); }, {"x.png", "CV_32FC1"});
}

TEST(IoImage, LabelsAndRgb) {
  const auto dir = fresh_temp_dir();
  cv::Mat labels(3, 5, CV_16UC1);
  for (int i = 0; i < 15; ++i) labels.at<std::uint16_t>(i / 5, i % 5) = static_cast<std::uint16_t>(i * 1000);
  write_label_png((dir / "l.png").string(), labels);
  const cv::Mat back = read_label_png((dir / "l.png").string(), {5, 3});
  EXPECT_EQ(cv::countNonZero(back != labels), 0);
  cv::Mat rgb(3, 5, CV_8UC3, cv::Scalar(10, 20, 30));
  write_rgb_png((dir / "c.png").string(), rgb);
  const cv::Mat c = read_rgb((dir / "c.png").string(), {5, 3});
  ASSERT_EQ(c.type(), CV_8UC3);
  EXPECT_EQ(c.at<cv::Vec3b>(2, 4), cv::Vec3b(10, 20, 30));
  expect_error([&] { read_rgb((dir / "c.png").string(), {640, 480}); }, {"c.png", "image is 5x3", "640x480"});
  expect_error([&] { read_label_png((dir / "c.png").string()); }, {"c.png", "8-bit unsigned 3-channel", "single-channel"});
  cv::imwrite((dir / "c16.png").string(), cv::Mat(2, 2, CV_16UC3, cv::Scalar(1, 2, 3)));
  expect_error([&] { read_rgb((dir / "c16.png").string()); }, {"c16.png", "16-bit unsigned", "8-bit colour"});
}
