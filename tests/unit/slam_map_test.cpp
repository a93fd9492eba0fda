// Map bookkeeping: observations on both sides, covisibility weights, duplicate merging, keyframe
// erasure with pose resolution, and loop-style pose correction moving points.
#include <gtest/gtest.h>

#include "s3m/core/error.hpp"
#include "s3m/slam/map/map.hpp"

namespace s3m::slam {
namespace {

std::shared_ptr<const features::FrameFeatures> fake_features(int n) {
  auto f = std::make_shared<features::FrameFeatures>();
  f->pyramid = features::ScalePyramid::make(1.2, 4, 1.0);
  for (int i = 0; i < n; ++i) {
    cv::KeyPoint k(cv::Point2f(100.0f + i, 100.0f), 31.0f);
    k.octave = i % 2;
    f->keypoints.push_back(k);
  }
  f->descriptors = cv::Mat::zeros(n, 32, CV_8U);
  for (int i = 0; i < n; ++i) f->descriptors.at<std::uint8_t>(i, i % 32) = 0xFF;
  f->depth_m.assign(n, 2.0f);
  f->u_right.assign(n, 80.0f);
  f->depth_sigma_m.assign(n, 0.01f);
  return f;
}

KeyframeId add_kf(Map& m, int n, const SE3& T_w_c) {
  KeyFrame k;
  k.features = fake_features(n);
  k.points.assign(n, kNoId);
  k.T_w_c = T_w_c;
  return m.add_keyframe(std::move(k));
}

TEST(Map, ObservationsAndCovisibility) {
  Map m;
  const KeyframeId a = add_kf(m, 40, SE3::Identity());
  const KeyframeId b = add_kf(m, 40, make_se3(Vec3(0.1, 0, 0), Quat::Identity()));
  std::vector<PointId> pts;
  for (int i = 0; i < 20; ++i) pts.push_back(m.add_point(Vec3(0.1 * i, 0, 2), a, i));
  for (int i = 0; i < 16; ++i) m.add_observation(pts[i], b, i + 5);
  m.update_covisibility(b);
  EXPECT_EQ(m.keyframe(b).covisibility.at(a), 16);
  EXPECT_EQ(m.keyframe(a).covisibility.at(b), 16);
  EXPECT_EQ(m.keyframe(b).parent, a);
  EXPECT_EQ(m.keyframe(b).points[5], pts[0]);
  EXPECT_EQ(m.point(pts[3]).observations.at(b), 8);
  // Erasing observations below the edge threshold keeps the single strongest edge.
  for (int i = 0; i < 10; ++i) m.erase_observation(pts[i], b);
  m.update_covisibility(b);
  EXPECT_EQ(m.keyframe(b).covisibility.at(a), 6);
  EXPECT_EQ(m.keyframe(b).points[5], kNoId);
}

TEST(Map, ReplacePointMergesObservations) {
  Map m;
  const KeyframeId a = add_kf(m, 10, SE3::Identity());
  const KeyframeId b = add_kf(m, 10, SE3::Identity());
  const PointId p = m.add_point(Vec3(0, 0, 2), a, 1);
  const PointId q = m.add_point(Vec3(0, 0, 2.01), b, 2);
  m.replace_point(q, p);
  EXPECT_FALSE(m.has_point(q));
  EXPECT_EQ(m.point(p).observations.size(), 2u);
  EXPECT_EQ(m.keyframe(b).points[2], p);
  EXPECT_EQ(m.point(p).n_visible, 2);
}

TEST(Map, ErasedKeyframePoseStillResolves) {
  Map m;
  const SE3 T0 = SE3::Identity(), T1 = make_se3(Vec3(1, 0, 0), Quat::Identity()),
            T2 = make_se3(Vec3(2, 0, 0), Quat(Eigen::AngleAxisd(0.3, Vec3::UnitZ())));
  const KeyframeId a = add_kf(m, 30, T0), b = add_kf(m, 30, T1), c = add_kf(m, 30, T2);
  for (int i = 0; i < 20; ++i) {
    const PointId p = m.add_point(Vec3(i, 0, 3), a, i);
    m.add_observation(p, b, i);
    m.add_observation(p, c, i);
  }
  m.update_covisibility(b);
  m.update_covisibility(c);
  EXPECT_EQ(m.keyframe(c).parent, a);  // ties broken by the smaller id
  m.erase_keyframe(b);
  EXPECT_FALSE(m.has_keyframe(b));
  EXPECT_TRUE(m.resolve_T_w_kf(b).isApprox(T1, 1e-12));
  // A correction of the parent carries the erased keyframe along.
  const SE3 shift = make_se3(Vec3(0, 0.5, 0), Quat::Identity());
  m.apply_corrected_poses({{a, shift * T0}});
  EXPECT_TRUE(m.resolve_T_w_kf(b).isApprox(shift * T1, 1e-12));
  EXPECT_TRUE(m.point(0).p_w.isApprox(Vec3(0, 0.5, 3), 1e-12));  // ref keyframe a moved it
  EXPECT_THROW(m.resolve_T_w_kf(99), Error);
}

TEST(Map, PredictLevelFromDistanceRange) {
  const auto pyr = features::ScalePyramid::make(1.2, 8, 1.0);
  EXPECT_EQ(predict_level(2.0, 2.0, pyr), 0);
  EXPECT_EQ(predict_level(2.0 / 1.1, 2.0, pyr), 1);
  EXPECT_EQ(predict_level(2.0 / 1.44 - 1e-6, 2.0, pyr), 3);  // just closer than level 2's limit
  EXPECT_EQ(predict_level(0.01, 2.0, pyr), 7);
}

}  // namespace
}  // namespace s3m::slam
