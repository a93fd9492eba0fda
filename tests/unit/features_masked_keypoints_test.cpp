// Keypoints on masked pixels (things that move) leave with their descriptors.
#include <gtest/gtest.h>

#include "s3m/features/frame_features.hpp"

namespace s3m::features {
namespace {

TEST(MaskedKeypoints, DropsThoseOnTheMaskAndKeepsDescriptorsAligned) {
  std::vector<cv::KeyPoint> kps{{10.4f, 5.0f, 7}, {50.0f, 20.9f, 7}, {99.9f, 79.9f, 7}, {0.0f, 0.0f, 7}};
  cv::Mat desc(4, 32, CV_8U);
  for (int i = 0; i < 4; ++i) desc.row(i).setTo(i + 1);
  cv::Mat mask = cv::Mat::zeros(80, 100, CV_8UC1);
  mask.at<std::uint8_t>(20, 50) = 255;  // keypoint 1 (pixel 50, 20)
  mask.at<std::uint8_t>(79, 99) = 255;  // keypoint 2
  EXPECT_EQ(drop_masked_keypoints(kps, desc, mask), 2);
  ASSERT_EQ(kps.size(), 2u);
  ASSERT_EQ(desc.rows, 2);
  EXPECT_FLOAT_EQ(kps[0].pt.x, 10.4f);
  EXPECT_FLOAT_EQ(kps[1].pt.x, 0.0f);
  EXPECT_EQ(desc.at<std::uint8_t>(0, 31), 1);
  EXPECT_EQ(desc.at<std::uint8_t>(1, 0), 4);
  // Nothing masked: nothing changes.
  EXPECT_EQ(drop_masked_keypoints(kps, desc, cv::Mat::zeros(80, 100, CV_8UC1)), 0);
  EXPECT_EQ(kps.size(), 2u);
}

}  // namespace
}  // namespace s3m::features
