// The dynamic pixels of the last segmented frame, moved into the next one.
#include <gtest/gtest.h>

#include "s3m/core/camera.hpp"
#include "s3m/pipeline/dynamic_mask.hpp"

namespace s3m::pipeline {
namespace {

PinholeCamera camera() {
  PinholeCamera c;
  c.width = 640;
  c.height = 480;
  c.fx = c.fy = 500;
  c.cx = 320;
  c.cy = 240;
  return c;
}

// A person (class 14) at 2 m filling columns [300, 340) and rows [200, 280), wall elsewhere.
void person_frame(cv::Mat& argmax, cv::Mat& depth) {
  argmax = cv::Mat(480, 640, CV_16UC1, cv::Scalar(cls::kWall));
  argmax(cv::Rect(300, 200, 40, 80)).setTo(cls::kPerson);
  depth = cv::Mat(480, 640, CV_32FC1, cv::Scalar(4.0f));
  depth(cv::Rect(300, 200, 40, 80)).setTo(2.0f);
}

TEST(DynamicMask, SamePoseGivesTheBlockGrownByTheMargin) {
  DynamicMasker masker(camera(), {cls::kPerson}, 10);
  EXPECT_TRUE(masker.mask(SE3::Identity()).empty());  // no reference yet
  cv::Mat argmax, depth;
  person_frame(argmax, depth);
  masker.set_reference(argmax, depth, SE3::Identity());
  const cv::Mat m = masker.mask(SE3::Identity());
  ASSERT_EQ(m.type(), CV_8UC1);
  // Samples every 2 px from column 300 to 338 grown by 10 + 2 px: columns 288..350.
  EXPECT_EQ(m.at<std::uint8_t>(240, 288), 255);
  EXPECT_EQ(m.at<std::uint8_t>(240, 287), 0);
  EXPECT_EQ(m.at<std::uint8_t>(240, 350), 255);
  EXPECT_EQ(m.at<std::uint8_t>(240, 351), 0);
  EXPECT_EQ(m.at<std::uint8_t>(188, 320), 255);
  EXPECT_EQ(m.at<std::uint8_t>(187, 320), 0);
}

TEST(DynamicMask, AMovedCameraSeesTheBlockShiftedByItsDepth) {
  DynamicMasker masker(camera(), {cls::kPerson}, 0);
  cv::Mat argmax, depth;
  person_frame(argmax, depth);
  masker.set_reference(argmax, depth, SE3::Identity());
  // Camera 0.2 m to the right: points at 2 m move 500 * 0.2 / 2 = 50 px to the left.
  SE3 T_w_c = SE3::Identity();
  T_w_c.translation() = Eigen::Vector3d(0.2, 0, 0);
  const cv::Mat m = masker.mask(T_w_c);
  EXPECT_EQ(m.at<std::uint8_t>(240, 250), 255);  // was column 300
  EXPECT_EQ(m.at<std::uint8_t>(240, 247), 0);    // 250 - stride 2 - 1
  EXPECT_EQ(m.at<std::uint8_t>(240, 320), 0);    // the old place is free again
  EXPECT_EQ(cv::countNonZero(m(cv::Rect(0, 0, 640, 185))), 0);
}

TEST(DynamicMask, MapLabelsGrowAroundPeopleAndTakeTheTrackingMask) {
  // 1 label per pixel: wall everywhere, a person at column 10 of row 5.
  semantics::LabelMap l;
  l.ids = cv::Mat(10, 20, CV_16UC1, cv::Scalar(cls::kWall));
  l.probs = cv::Mat(10, 20, CV_32FC1, cv::Scalar(0.8f));
  l.argmax = l.ids;
  l.ids.at<std::uint16_t>(5, 10) = cls::kPerson;
  cv::Mat extra = cv::Mat::zeros(10, 20, CV_8UC1);
  extra.at<std::uint8_t>(0, 0) = 255;  // what the frames before saw move
  const semantics::LabelMap g = grow_dynamic_labels(l, {cls::kPerson}, 2, extra);
  EXPECT_EQ(g.argmax.at<std::uint16_t>(3, 8), cls::kPerson);  // 2 px away diagonally
  EXPECT_FLOAT_EQ(g.probs.at<float>(3, 8), 1.0f);
  EXPECT_EQ(g.argmax.at<std::uint16_t>(2, 10), cls::kWall);  // 3 px away
  EXPECT_EQ(g.argmax.at<std::uint16_t>(0, 0), cls::kPerson);
  EXPECT_EQ(cv::countNonZero(g.argmax == cls::kPerson), 25 + 1);
  EXPECT_EQ(l.ids.at<std::uint16_t>(3, 8), cls::kWall);  // the segmentation itself is unchanged
  // Nothing dynamic: the same labels back.
  const semantics::LabelMap same = grow_dynamic_labels(l, {cls::kChair}, 2);
  EXPECT_EQ(same.ids.data, l.ids.data);
  // The labels' own mask: person pixels grown by 1.
  EXPECT_EQ(cv::countNonZero(label_mask(l.argmax, {cls::kPerson}, 1)), 9);
}

TEST(DynamicMask, ConstantVelocityPrediction) {
  SE3 a = SE3::Identity(), b = SE3::Identity();
  b.translation() = Eigen::Vector3d(0.1, 0, 0);
  EXPECT_TRUE(predict_pose(a, b).translation().isApprox(Eigen::Vector3d(0.2, 0, 0)));
}

}  // namespace
}  // namespace s3m::pipeline
