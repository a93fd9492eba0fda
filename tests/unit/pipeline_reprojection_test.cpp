// Map-label reprojection score on a hand-built map with known answers, and the bounded frame sampler.
#include <gtest/gtest.h>

#include "s3m/core/error.hpp"
#include "s3m/pipeline/reprojection.hpp"

using namespace s3m;
using namespace s3m::pipeline;

namespace {
constexpr double kRes = 0.1;

// A 4x3-pixel camera looking down +z; pixel columns 0-1 see x < 0, columns 2-3 see x > 0 at 2 m.
PinholeCamera camera() {
  PinholeCamera c;
  c.fx = c.fy = 2.0;
  c.cx = 2.0, c.cy = 1.5;
  c.width = 4, c.height = 3;
  return c;
}

// A wall at z = 2 m (the voxel layer [2.0, 2.1), x and y in [-4, 4) x [-2, 2)): x < 0 table, x >= 0 chair.
mapping::SemanticOcTree wall_map() {
  mapping::SemanticOcTree t(kRes);
  for (int i = -40; i < 40; ++i)
    for (int j = -20; j < 20; ++j) {
      const auto key = t.coordToKey((i + 0.5) * kRes, (j + 0.5) * kRes, 2.05);
      t.updateNode(key, 2.0f, true);
      mapping::LabelSet s;
      s.push(i < 0 ? cls::kTable : cls::kChair, 0.9f);
      t.integrateObservation(key, s, {1, 2, 3});
    }
  t.updateInnerOccupancy();
  return t;
}

cv::Mat labels(std::initializer_list<std::uint16_t> row, int rows = 3) {
  cv::Mat m(rows, int(row.size()), CV_16UC1);
  for (int v = 0; v < rows; ++v) {
    int u = 0;
    for (auto l : row) m.at<std::uint16_t>(v, u++) = l;
  }
  return m;
}
}  // namespace

TEST(Reprojection, MapAndFrameScoredOnTheSamePixels) {
  const auto map = wall_map();
  ReprojectionInput in;
  in.depth_m = cv::Mat(3, 4, CV_32FC1, cv::Scalar(2.04f));  // inside the wall's voxel layer
  in.depth_m.at<float>(0, 0) = 9.0f;                         // beyond max range: not evaluated
  in.depth_m.at<float>(1, 0) = 1.0f;                         // in range, but free/unknown there: not covered
  in.gt_labels = labels({cls::kTable, cls::kTable, cls::kChair, cls::kChair});
  in.gt_labels.at<std::uint16_t>(2, 3) = cls::kUnknown;      // no ground truth: not evaluated
  in.frame_pred = labels({cls::kTable, cls::kTable, cls::kTable, cls::kTable});
  in.T_w_c = SE3::Identity();
  ReprojectionScore s;
  add_reprojection(map, camera(), in, {0.3, 4.0, 1}, s);
  EXPECT_EQ(s.frames, 1);
  EXPECT_EQ(s.evaluated_px, 12 - 2);  // 1 beyond range, 1 without ground truth
  EXPECT_EQ(s.covered_px, 12 - 3);    // and 1 whose point lies in unknown space
  // Covered: table GT at (0,1) (1,1) (2,0) (2,1) = 4 px, chair GT at (0,2) (0,3) (1,2) (1,3) (2,2) = 5 px.
  const auto m = s.map.metrics(), f = s.frame.metrics();
  EXPECT_DOUBLE_EQ(m.miou, 1.0);  // the map is right on every covered pixel
  EXPECT_DOUBLE_EQ(f.iou[cls::kTable], 4.0 / 9.0);
  EXPECT_DOUBLE_EQ(f.iou[cls::kChair], 0.0);
  EXPECT_DOUBLE_EQ(f.miou, 2.0 / 9.0);
  EXPECT_NEAR(s.coverage(), 0.9, 1e-12);
}

TEST(Reprojection, SurfaceHalfAVoxelOffFindsTheNeighbourAlongTheRay) {
  const auto map = wall_map();
  ReprojectionInput in;
  in.depth_m = cv::Mat(3, 4, CV_32FC1, cv::Scalar(1.96f));  // 4 cm in front of the wall's layer
  in.gt_labels = labels({cls::kTable, cls::kTable, cls::kChair, cls::kChair});
  in.frame_pred = in.gt_labels.clone();
  // The camera 1 m behind the origin: points land at z = 0.96 m, the map's voxels are at 2 m.
  ReprojectionScore far;
  in.T_w_c = SE3(Eigen::Translation3d(0, 0, -1.0));
  add_reprojection(map, camera(), in, {0.3, 4.0, 1}, far);
  EXPECT_EQ(far.covered_px, 0);
  ReprojectionScore near;
  in.T_w_c = SE3::Identity();
  add_reprojection(map, camera(), in, {0.3, 4.0, 1}, near);
  EXPECT_EQ(near.covered_px, 12);
}

TEST(Reprojection, RejectsMismatchedImages) {
  const auto map = wall_map();
  ReprojectionInput in;
  in.depth_m = cv::Mat(3, 4, CV_32FC1, cv::Scalar(2.0f));
  in.gt_labels = cv::Mat(3, 5, CV_16UC1, cv::Scalar(1));
  in.frame_pred = cv::Mat(3, 4, CV_16UC1, cv::Scalar(1));
  ReprojectionScore s;
  EXPECT_THROW(add_reprojection(map, camera(), in, {}, s), Error);
}

TEST(EvalFrameSampler, KeepsAnEvenlySpreadBoundedSubset) {
  EvalFrameSampler sampler(1, 4);
  for (std::size_t i = 0; i < 10; ++i)
    if (sampler.wants(i)) sampler.keep({int(i), double(i), cv::Mat()}, i);
  // n = 1: 0 1 2 3 4 -> full, keep multiples of 2, n = 2: 0 2 4 6 8 -> full, multiples of 4, n = 4.
  std::vector<int> kept;
  for (const auto& f : sampler.frames()) kept.push_back(f.index);
  EXPECT_EQ(kept, (std::vector<int>{0, 4, 8}));
  EXPECT_FALSE(sampler.wants(10));
  EXPECT_TRUE(sampler.wants(12));
  EXPECT_FALSE(EvalFrameSampler(1, 0).wants(0));  // eval.reprojection_max_frames: 0 turns it off
}
