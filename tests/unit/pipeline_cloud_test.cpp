// Back-projection of labelled pixels, range filtering, voxel downsampling; segmentation confusion.
#include <gtest/gtest.h>

#include "s3m/pipeline/cloud_from_frame.hpp"

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
  depth.at<float>(0, 0) = 0.1f;           // too close
  depth.at<float>(0, 1) = 9.0f;           // too far
  depth.at<float>(0, 2) = std::nanf("");  // missing
  depth.at<float>(0, 3) = 0.0f;           // missing
  cv::Mat bgr(4, 4, CV_8UC3, cv::Scalar(10, 20, 30));
  bgr.at<cv::Vec3b>(3, 3) = {1, 2, 3};
  semantics::LabelMap labels = semantics::make_label_map(4, 4, 2);
  labels.ids.at<cv::Vec<ClassId, 2>>(3, 3) = {cls::kChair, cls::kSofa};
  labels.probs.at<cv::Vec2f>(3, 3) = {0.7f, 0.2f};

  const mapping::LabeledCloud c = backproject(cam, depth, bgr, labels, {0.2, 4.0, 1});
  ASSERT_EQ(c.size(), 12u);  // 16 pixels minus the 4 of row 0
  ASSERT_EQ(c.k, 2);
  EXPECT_NO_THROW(c.validate());
  EXPECT_EQ(c.origin, Eigen::Vector3f::Zero());  // camera frame
  const auto& last = c.points.back();            // pixel (u=3, v=3) at z = 2: x = (3 - 1.5) * 2 / 2 = 1.5
  EXPECT_FLOAT_EQ(last.x(), 1.5f);
  EXPECT_FLOAT_EQ(last.y(), 1.5f);
  EXPECT_FLOAT_EQ(last.z(), 2.0f);
  EXPECT_EQ(c.rgb[3 * 11 + 0], 3);  // BGR (1, 2, 3) in the image -> RGB (3, 2, 1) in the cloud
  EXPECT_EQ(c.rgb[3 * 11 + 2], 1);
  EXPECT_EQ(c.labels[2 * 11], cls::kChair);
  EXPECT_EQ(c.labels[2 * 11 + 1], cls::kSofa);
  EXPECT_FLOAT_EQ(c.probs[2 * 11], 0.7f);
  EXPECT_EQ(c.labels[0], cls::kUnknown);  // unlabelled pixel

  const mapping::LabeledCloud strided = backproject(cam, depth, bgr, {}, {0.2, 4.0, 2});
  EXPECT_EQ(strided.size(), 2u);  // (0,2),(2,2) kept of (0,0),(2,0),(0,2),(2,2); row 0 is filtered
  EXPECT_EQ(strided.k, 0);
  EXPECT_TRUE(strided.labels.empty());
}

TEST(Transformed, MovesPointsAndOrigin) {
  mapping::LabeledCloud c;
  c.push_back({1, 0, 0}, 1, 2, 3);
  const SE3 T_w_c = make_se3(Vec3(0, 0, 1), Quat(Eigen::AngleAxisd(M_PI / 2, Vec3::UnitZ())));
  const mapping::LabeledCloud w = transformed(c, T_w_c);
  EXPECT_TRUE(w.points[0].isApprox(Eigen::Vector3f(0, 1, 1), 1e-6f));
  EXPECT_TRUE(w.origin.isApprox(Eigen::Vector3f(0, 0, 1), 1e-6f));
  EXPECT_EQ(w.rgb, c.rgb);
}

TEST(VoxelDownsample, KeepsTheFirstPointPerVoxel) {
  mapping::LabeledCloud c;
  c.k = 1;
  const std::vector<Eigen::Vector3f> pts = {
      {0.01f, 0.01f, 1.01f}, {0.04f, 0.02f, 1.03f}, {0.06f, 0.0f, 1.0f}, {-0.01f, 0.0f, 1.0f}};
  for (std::size_t i = 0; i < pts.size(); ++i) {
    const ClassId id = static_cast<ClassId>(i + 1);
    const float p = 0.5f;
    c.push_back(pts[i], static_cast<std::uint8_t>(i), 0, 0, &id, &p);
  }
  const mapping::LabeledCloud d = voxel_downsample(c, 0.05);
  ASSERT_EQ(d.size(), 3u);  // points 0 and 1 share the voxel [0, 0.05)^2 x [1.0, 1.05)
  EXPECT_EQ(d.labels, (std::vector<ClassId>{1, 3, 4}));
  EXPECT_EQ(d.rgb[3], 2);
  EXPECT_EQ(voxel_downsample(c, 0.0).size(), 4u);
}

}  // namespace
}  // namespace s3m::pipeline
