#include <gtest/gtest.h>

#include <cmath>

#include "s3m/core/error.hpp"
#include "s3m/semantics/label_map.hpp"

using namespace s3m;
using namespace s3m::semantics;

namespace {
std::vector<cv::Mat> planes_from(const std::vector<std::vector<float>>& per_class, int rows, int cols) {
  std::vector<cv::Mat> planes;
  for (const auto& v : per_class) planes.push_back(cv::Mat(rows, cols, CV_32FC1, const_cast<float*>(v.data())).clone());
  return planes;
}
}  // namespace

TEST(SemanticsLabelMap, SoftmaxMatchesHandComputedValues) {
  // One pixel with logits (0, ln 2, ln 5): exp = 1, 2, 5 -> 1/8, 2/8, 5/8.
  // Second pixel with huge equal logits (stability): 1/3 each.
  auto planes = planes_from({{0.f, 1000.f}, {std::log(2.f), 1000.f}, {std::log(5.f), 1000.f}}, 1, 2);
  softmax_planes(planes);
  EXPECT_NEAR(planes[0].at<float>(0, 0), 0.125f, 1e-6);
  EXPECT_NEAR(planes[1].at<float>(0, 0), 0.25f, 1e-6);
  EXPECT_NEAR(planes[2].at<float>(0, 0), 0.625f, 1e-6);
  for (int i = 0; i < 3; ++i) EXPECT_NEAR(planes[i].at<float>(0, 1), 1.f / 3.f, 1e-6);
}

TEST(SemanticsLabelMap, TopKOrdersByProbabilityAndKeepsIds) {
  // 4 classes with ids 3, 5, 7, 9; pixel 0 probs (0.1, 0.4, 0.2, 0.3), pixel 1 (0.7, 0.1, 0.1, 0.1).
  const auto planes = planes_from({{0.1f, 0.7f}, {0.4f, 0.1f}, {0.2f, 0.1f}, {0.3f, 0.1f}}, 1, 2);
  const LabelMap m = topk_from_planes(planes, {3, 5, 7, 9}, 3);
  ASSERT_EQ(m.k(), 3);
  ASSERT_EQ(m.ids.type(), CV_16UC(3));
  ASSERT_EQ(m.probs.type(), CV_32FC(3));
  EXPECT_EQ(m.id(0, 0, 0), 5);
  EXPECT_EQ(m.id(0, 0, 1), 9);
  EXPECT_EQ(m.id(0, 0, 2), 7);
  EXPECT_FLOAT_EQ(m.prob(0, 0, 0), 0.4f);
  EXPECT_FLOAT_EQ(m.prob(0, 0, 1), 0.3f);
  EXPECT_FLOAT_EQ(m.prob(0, 0, 2), 0.2f);
  // ties (0.1, 0.1, 0.1) keep the earlier plane first
  EXPECT_EQ(m.id(0, 1, 0), 3);
  EXPECT_EQ(m.id(0, 1, 1), 5);
  EXPECT_EQ(m.id(0, 1, 2), 7);
  EXPECT_EQ(m.argmax.at<ClassId>(0, 0), 5);
  EXPECT_EQ(m.argmax.at<ClassId>(0, 1), 3);
}

TEST(SemanticsLabelMap, TopKLargerThanClassCountPadsWithUnknown) {
  const auto planes = planes_from({{0.25f}, {0.75f}}, 1, 1);
  const LabelMap m = topk_from_planes(planes, {1, 2}, 4);
  EXPECT_EQ(m.id(0, 0, 0), 2);
  EXPECT_EQ(m.id(0, 0, 1), 1);
  EXPECT_EQ(m.id(0, 0, 2), 0);
  EXPECT_EQ(m.prob(0, 0, 3), 0.f);
}

TEST(SemanticsLabelMap, ColorizeUsesPaletteAndFlagsBadIds) {
  cv::Mat ids = (cv::Mat_<ClassId>(1, 2) << cls::kFloor, 999);
  const cv::Mat c = colorize(ids, indoor_classes());
  const auto& floor = indoor_classes().at(cls::kFloor);
  EXPECT_EQ(c.at<cv::Vec3b>(0, 0), cv::Vec3b(floor.b, floor.g, floor.r));
  EXPECT_EQ(c.at<cv::Vec3b>(0, 1), cv::Vec3b(255, 0, 255));
  EXPECT_THROW(colorize(cv::Mat(2, 2, CV_8UC1), indoor_classes()), Error);
}
