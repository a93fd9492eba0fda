// match_covisible_group: which map points of a keyframe's covisibility group it predicts into a
// frame and matches, on a hand-built map whose points project to known keypoints.
#include <gtest/gtest.h>

#include <algorithm>
#include <map>

#include "s3m/slam/map/group_search.hpp"

namespace s3m::slam {
namespace {

// Descriptor i: bytes i and (i + 11) % 32 set, so two different descriptors differ in 32 bits and
// a keypoint only matches its own point (Hamming 0).
void set_descriptor(cv::Mat& d, int row, int i) {
  d.row(row).setTo(0);
  d.at<std::uint8_t>(row, i % 32) = 0xFF;
  d.at<std::uint8_t>(row, (i + 11) % 32) = 0xFF;
}

// Features at the given pixels (level 0), descriptor ids[k] for pixel k, depth 2 m.
std::shared_ptr<features::FrameFeatures> features_at(const std::vector<Eigen::Vector2d>& px,
                                                     const std::vector<int>& ids) {
  auto f = std::make_shared<features::FrameFeatures>();
  f->pyramid = features::ScalePyramid::make(1.2, 4, 1.0);
  f->descriptors = cv::Mat::zeros(static_cast<int>(px.size()), 32, CV_8U);
  for (std::size_t k = 0; k < px.size(); ++k) {
    cv::KeyPoint kp(cv::Point2f(float(px[k].x()), float(px[k].y())), 31.0f);
    kp.octave = 0;
    f->keypoints.push_back(kp);
    set_descriptor(f->descriptors, int(k), ids[k]);
  }
  f->depth_m.assign(px.size(), 2.0f);
  f->u_right.assign(px.size(), features::kNoRight);
  f->depth_sigma_m.assign(px.size(), 0.0f);
  f->grid.build(f->keypoints, 640, 480);
  return f;
}

struct GroupMap {
  PinholeCamera cam;
  Map map;
  KeyframeId a = kNoId, b = kNoId;
  std::vector<PointId> pid;  // point i: descriptor i
  std::vector<Vec3> p_w;
};

// Keyframe a (identity) sees points 0-5, keyframe b (5 cm to the right) sees points 3-8, so a
// and b are covisible through points 3-5; points 6-8 are reachable from a only through b.
GroupMap make_group_map() {
  GroupMap g;
  for (int i = 0; i < 9; ++i) g.p_w.emplace_back(-0.4 + 0.1 * i, 0.05 * (i % 3), 2.0);
  const SE3 T_w_b = make_se3(Vec3(0.05, 0, 0), Quat::Identity());
  auto view = [&](const SE3& T_w_c, int first, int last) {
    std::vector<Eigen::Vector2d> px;
    std::vector<int> ids;
    for (int i = first; i <= last; ++i) {
      px.push_back(g.cam.project(T_w_c.inverse() * g.p_w[size_t(i)]));
      ids.push_back(i);
    }
    KeyFrame k;
    k.T_w_c = T_w_c;
    k.features = features_at(px, ids);
    k.points.assign(px.size(), kNoId);
    return k;
  };
  g.a = g.map.add_keyframe(view(SE3::Identity(), 0, 5));
  g.b = g.map.add_keyframe(view(T_w_b, 3, 8));
  g.pid.assign(9, kNoId);
  for (int i = 0; i <= 5; ++i) g.pid[size_t(i)] = g.map.add_point(g.p_w[size_t(i)], g.a, i);
  for (int i = 3; i <= 5; ++i) g.map.add_observation(g.pid[size_t(i)], g.b, i - 3);
  for (int i = 6; i <= 8; ++i) g.pid[size_t(i)] = g.map.add_point(g.p_w[size_t(i)], g.b, i - 3);
  for (PointId p : g.pid) g.map.update_point_appearance(p);
  g.map.update_covisibility(g.a);
  g.map.update_covisibility(g.b);
  return g;
}

// Query frame 2 cm up from a, with one keypoint per point 0-8 at its projection, in reverse order
// so keypoint index != point index. Returns point index -> keypoint index matched.
// predict_offset_m: the pose handed to the search is off by this much along x.
std::map<int, int> run(const GroupMap& g, const GroupSearchParams& params, double predict_offset_m = 0.0) {
  const SE3 T_w_q = make_se3(Vec3(0.01, 0.02, 0), Quat::Identity());
  const SE3 T_w_guess = make_se3(Vec3(0.01 + predict_offset_m, 0.02, 0), Quat::Identity());
  std::vector<Eigen::Vector2d> px;
  std::vector<int> ids;
  for (int i = 8; i >= 0; --i) {
    px.push_back(g.cam.project(T_w_q.inverse() * g.p_w[size_t(i)]));
    ids.push_back(i);
  }
  const auto f = features_at(px, ids);
  std::map<int, int> out;
  for (const auto& [kp, pid] : match_covisible_group(*f, g.map, g.a, T_w_guess, g.cam, params)) {
    const int i = int(std::find(g.pid.begin(), g.pid.end(), pid) - g.pid.begin());
    EXPECT_TRUE(out.emplace(i, kp).second) << "point " << i << " matched twice";
  }
  return out;
}

TEST(GroupSearch, MatchesEveryPointOfTheGroupToItsOwnKeypoint) {
  const GroupMap g = make_group_map();
  const auto m = run(g, {});
  ASSERT_EQ(m.size(), 9u);  // a's points 0-5 and, through covisible b, 6-8
  for (const auto& [i, kp] : m) EXPECT_EQ(kp, 8 - i) << "point " << i;
}

TEST(GroupSearch, GroupSizeZeroSearchesOnlyTheKeyframe) {
  const GroupMap g = make_group_map();
  GroupSearchParams p;
  p.group_size = 0;
  const auto m = run(g, p);
  ASSERT_EQ(m.size(), 6u);
  for (int i = 0; i <= 5; ++i) EXPECT_EQ(m.count(i), 1u) << "point " << i;
}

TEST(GroupSearch, SkipsPointsTheGivenKeyframeObserves) {
  const GroupMap g = make_group_map();
  GroupSearchParams p;
  p.skip_observed_by = g.b;  // b sees 3-8: only a's own 0-2 are left
  const auto m = run(g, p);
  ASSERT_EQ(m.size(), 3u);
  for (int i = 0; i <= 2; ++i) EXPECT_EQ(m.at(i), 8 - i);
}

TEST(GroupSearch, APoseErrorBeyondTheWindowFindsNothing) {
  const GroupMap g = make_group_map();
  // 4 cm off at 2 m shifts every prediction by 525 * 0.04 / 2 = 10.5 px. The predicted level is
  // 0 or 1 (the query is a little farther than keyframe a), so the window is factor x 1 or x 1.2.
  GroupSearchParams p;
  p.radius_factor = 8.0;  // at most 9.6 px
  EXPECT_TRUE(run(g, p, 0.04).empty());
  p.radius_factor = 11.0;
  EXPECT_EQ(run(g, p, 0.04).size(), 9u);
}

}  // namespace
}  // namespace s3m::slam
