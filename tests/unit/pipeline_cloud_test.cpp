// Back-projection of labelled pixels, range filtering, voxel downsampling; segmentation confusion.
#include <gtest/gtest.h>

#include "s3m/pipeline/labelled_cloud.hpp"
#include "s3m/pipeline/progress.hpp"

namespace s3m::pipeline {
namespace {

PinholeCamera tiny_camera() {
  PinholeCamera c;
  c.fx = c.fy = 2.0;
  c.cx = c.cy = 1.5;
  c.width = c.height = 4;
  return c;
}

TEST(Backproject, KeepsInRangePixelsWithColourAndLabels) {
  const PinholeCamera cam = tiny_camera();
  cv::Mat depth(4, 4, CV_32F, cv::Scalar(2.0f));
  depth.at<float>(0, 0) = 0.1f;                 // too close
  depth.at<float>(0, 1) = 9.0f;                 // too far
  depth.at<float>(0, 2) = std::nanf("");        // missing
  depth.at<float>(0, 3) = 0.0f;                 // missing
  cv::Mat bgr(4, 4, CV_8UC3, cv::Scalar(10, 20, 30));
  bgr.at<cv::Vec3b>(3, 3) = {1, 2, 3};
  semantics::LabelMap labels = semantics::make_label_map(4, 4, 2);
  labels.ids.at<cv::Vec<ClassId, 2>>(3, 3) = {cls::kChair, cls::kSofa};
  labels.probs.at<cv::Vec2f>(3, 3) = {0.7f, 0.2f};

  const LabelledCloud c = backproject(cam, depth, bgr, labels, {0.2, 4.0, 1});
  ASSERT_EQ(c.size(), 12u);  // 16 pixels minus the 4 of row 0
  ASSERT_EQ(c.k, 2);
  const auto& last = c.p_c.back();  // pixel (u=3, v=3) at z = 2: x = (3 - 1.5) * 2 / 2 = 1.5
  EXPECT_FLOAT_EQ(last.x(), 1.5f);
  EXPECT_FLOAT_EQ(last.y(), 1.5f);
  EXPECT_FLOAT_EQ(last.z(), 2.0f);
  EXPECT_EQ(c.bgr[3 * 11 + 0], 1);
  EXPECT_EQ(c.bgr[3 * 11 + 2], 3);
  EXPECT_EQ(c.ids[2 * 11], cls::kChair);
  EXPECT_EQ(c.ids[2 * 11 + 1], cls::kSofa);
  EXPECT_FLOAT_EQ(c.probs[2 * 11], 0.7f);
  EXPECT_EQ(c.ids[0], cls::kUnknown);  // unlabelled pixel

  const LabelledCloud strided = backproject(cam, depth, bgr, {}, {0.2, 4.0, 2});
  EXPECT_EQ(strided.size(), 2u);  // (0,2),(2,2) kept of (0,0),(2,0),(0,2),(2,2); row 0 is filtered
  EXPECT_EQ(strided.k, 0);
  EXPECT_TRUE(strided.ids.empty());
}

TEST(VoxelDownsample, KeepsTheFirstPointPerVoxel) {
  LabelledCloud c;
  c.k = 1;
  const std::vector<Eigen::Vector3f> pts = {{0.01f, 0.01f, 1.01f}, {0.04f, 0.02f, 1.03f}, {0.06f, 0.0f, 1.0f},
                                            {-0.01f, 0.0f, 1.0f}};
  for (std::size_t i = 0; i < pts.size(); ++i) {
    c.p_c.push_back(pts[i]);
    c.bgr.insert(c.bgr.end(), {static_cast<std::uint8_t>(i), 0, 0});
    c.ids.push_back(static_cast<ClassId>(i + 1));
    c.probs.push_back(0.5f);
  }
  const LabelledCloud d = voxel_downsample(c, 0.05);
  ASSERT_EQ(d.size(), 3u);  // points 0 and 1 share the voxel [0, 0.05)^2 x [1.0, 1.05)
  EXPECT_EQ(d.ids, (std::vector<ClassId>{1, 3, 4}));
  EXPECT_EQ(d.bgr[3], 2);
  EXPECT_EQ(voxel_downsample(c, 0.0).size(), 4u);
}

TEST(ProgressLine, FormatShowsRateStateAndEta) {
  EXPECT_EQ(ProgressLine::format(50, 200, 5.0, "OK"), "frames 50/200 (25%)  10.0 fps  OK  ETA 15 s");
  EXPECT_EQ(ProgressLine::format(0, 10, 0.0, "NOT_INITIALIZED"), "frames 0/10 (0%)  0.0 fps  NOT_INITIALIZED  ETA --");
}

}  // namespace
}  // namespace s3m::pipeline
