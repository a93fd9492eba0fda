#include <gtest/gtest.h>

#include <cmath>

#include "s3m/core/error.hpp"
#include "s3m/semantics/seg_metrics.hpp"

using namespace s3m;
using namespace s3m::semantics;

TEST(SemanticsMetrics, HandComputedIouAndAccuracy) {
  // GT:   1 1 2 2 0      Pred: 1 2 2 2 1     (0 = unknown, not evaluated)
  const cv::Mat gt = (cv::Mat_<ClassId>(1, 5) << 1, 1, 2, 2, 0);
  const cv::Mat pred = (cv::Mat_<ClassId>(1, 5) << 1, 2, 2, 2, 1);
  ConfusionMatrix cm(4);
  cm.add(gt, pred);
  EXPECT_EQ(cm.at(1, 1), 1);
  EXPECT_EQ(cm.at(1, 2), 1);
  EXPECT_EQ(cm.at(2, 2), 2);
  const SegMetrics m = cm.metrics();
  // class 1: TP 1, FN 1, FP 0 -> 1/2; class 2: TP 2, FP 1 -> 2/3; class 3 absent -> NaN
  EXPECT_DOUBLE_EQ(m.iou[1], 0.5);
  EXPECT_DOUBLE_EQ(m.iou[2], 2.0 / 3.0);
  EXPECT_TRUE(std::isnan(m.iou[3]));
  EXPECT_DOUBLE_EQ(m.miou, (0.5 + 2.0 / 3.0) / 2.0);
  EXPECT_DOUBLE_EQ(m.pixel_accuracy, 0.75);
  EXPECT_EQ(m.evaluated_px, 4);
  // excluding class 2 from the mean
  EXPECT_DOUBLE_EQ(cm.metrics({2}).miou, 0.5);
}

TEST(SemanticsMetrics, AccumulatesAndRejectsMismatchedSizes) {
  ConfusionMatrix a(3), b(3);
  const cv::Mat ones(2, 2, CV_16UC1, cv::Scalar(1));
  a.add(ones, ones);
  b.add(ones, cv::Mat(2, 2, CV_16UC1, cv::Scalar(2)));
  a.add(b);
  EXPECT_EQ(a.at(1, 1), 4);
  EXPECT_EQ(a.at(1, 2), 4);
  EXPECT_THROW(a.add(ones, cv::Mat(3, 2, CV_16UC1, cv::Scalar(1))), Error);
  // predictions outside the class range count as "unknown" (wrong)
  ConfusionMatrix c(3);
  c.add(ones, cv::Mat(2, 2, CV_16UC1, cv::Scalar(77)));
  EXPECT_EQ(c.at(1, 0), 4);
  EXPECT_DOUBLE_EQ(c.metrics().pixel_accuracy, 0.0);
}

TEST(SemanticsMetrics, RenderDrawsOnlyPresentClasses) {
  ConfusionMatrix cm(cls::kCount);
  const cv::Mat gt = (cv::Mat_<ClassId>(1, 2) << cls::kWall, cls::kFloor);
  cm.add(gt, gt);
  const cv::Mat img = cm.render(indoor_classes());
  ASSERT_EQ(img.type(), CV_8UC3);
  // 2 classes shown: left margin 130 + 2 cells of 44 + 20
  EXPECT_EQ(img.cols, 130 + 2 * 44 + 20);
}
