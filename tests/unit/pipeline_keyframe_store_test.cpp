// Kept clouds follow keyframe corrections, including keyframes SLAM has culled since.
#include <gtest/gtest.h>

#include <limits>

#include "s3m/core/error.hpp"
#include "s3m/pipeline/cloud_from_frame.hpp"
#include "s3m/pipeline/keyframe_store.hpp"

namespace s3m::pipeline {
namespace {

SE3 at(double x, double y = 0, double yaw_rad = 0) {
  return make_se3(Vec3(x, y, 0), Quat(Eigen::AngleAxisd(yaw_rad, Vec3::UnitZ())));
}

bool near(const SE3& a, const SE3& b, double tol = 1e-12) {
  return (a.matrix() - b.matrix()).cwiseAbs().maxCoeff() < tol;
}

TEST(KeyframeStore, CloudsKeepTheirPoseRelativeToTheAnchor) {
  KeyframeStore s;
  s.note_keyframe(0, at(0));
  s.note_keyframe(1, at(1));
  s.add(0, at(0), 0, {});
  s.add(1, at(1.2, 0.1), 5, {});  // a non-keyframe riding on keyframe 1
  ASSERT_EQ(s.size(), 2u);
  EXPECT_TRUE(near(s.T_w_c(s.clouds()[1]), at(1.2, 0.1)));

  // Loop correction: keyframe 1 rotates by 90 deg about z and moves to (1, 1).
  const double shift = s.update_poses({{0, at(0)}, {1, at(1, 1, M_PI / 2)}});
  EXPECT_NEAR(shift, 1.0, 1e-12);
  // The rider keeps T_kf_c = (0.2, 0.1): rotated by 90 deg it lands at (1 - 0.1, 1 + 0.2).
  EXPECT_TRUE(near(s.T_w_c(s.clouds()[1]), at(0.9, 1.2, M_PI / 2)));
  EXPECT_TRUE(near(s.T_w_c(s.clouds()[0]), at(0)));
}

TEST(KeyframeStore, CulledKeyframesFollowTheirNearestNeighbour) {
  KeyframeStore s;
  for (int i = 0; i < 5; ++i) s.note_keyframe(i, at(i));
  s.add(2, at(2), 2, {});
  // SLAM culled keyframe 2 and corrects the others by a translation that grows along the path.
  const std::map<KeyframeId, SE3> corrected = {{0, at(0)}, {1, at(1, 0.1)}, {3, at(3, 0.3)}, {4, at(4, 0.4)}};
  s.update_poses(corrected);
  // Tie between 1 and 3: the older neighbour (1) wins; its correction is a 0.1 m shift in y.
  EXPECT_TRUE(near(s.T_w_c(s.clouds()[0]), at(2, 0.1)));
  EXPECT_TRUE(near(s.keyframes().at(4), at(4, 0.4)));
}

mapping::LabeledCloud cloud_of(int points) {
  mapping::LabeledCloud c;
  for (int i = 0; i < points; ++i) c.push_back(Eigen::Vector3f(0.01f * i, 0, 1), 1, 2, 3);
  return c;
}

// What a cloud of n points with colour and no labels holds once it fits exactly.
std::size_t exact_bytes(int points) { return std::size_t(points) * (sizeof(Eigen::Vector3f) + 3); }

std::vector<int> kept_frames(const KeyframeStore& s) {
  std::vector<int> out;
  for (const auto& c : s.clouds()) out.push_back(c.frame_index);
  return out;
}

TEST(KeyframeStore, BudgetDropsTheOldestRedundantViewAndKeepsKeyframes) {
  const std::size_t one = exact_bytes(100) + sizeof(KeptCloud);
  KeyframeStore s(4 * one + one / 2);  // room for four clouds
  s.note_keyframe(0, at(0));
  s.note_keyframe(3, at(5));
  s.note_keyframe(4, at(10));
  s.add(0, at(0), 0, cloud_of(100));    // keyframe cloud, cell x in [0, 0.5) m
  s.add(0, at(0.1), 1, cloud_of(100));  // riders in the same cell
  s.add(0, at(0.2), 2, cloud_of(100));
  s.add(3, at(5), 3, cloud_of(100));    // two other places
  EXPECT_EQ(s.dropped(), 0u);
  s.add(4, at(10), 4, cloud_of(100));
  // Over budget: the crowded cell loses its oldest rider (frame 1), not its keyframe cloud.
  EXPECT_EQ(kept_frames(s), (std::vector<int>{0, 2, 3, 4}));
  EXPECT_LE(s.bytes(), s.budget_bytes());
  // Revisiting the first place again and again: the newest view stays, older riders go, the keyframe
  // cloud and the other places survive.
  for (int f = 5; f < 9; ++f) s.add(0, at(0.05 * f), f, cloud_of(100));
  EXPECT_EQ(kept_frames(s), (std::vector<int>{0, 3, 4, 8}));
  EXPECT_EQ(s.dropped(), 5u);
  EXPECT_EQ(s.bytes(), 4 * one);
}

TEST(KeyframeStore, NoBudgetKeepsEveryCloud) {
  KeyframeStore s;
  s.note_keyframe(0, at(0));
  for (int f = 0; f < 50; ++f) s.add(0, at(0.01 * f), f, cloud_of(10));
  EXPECT_EQ(s.size(), 50u);
  EXPECT_EQ(s.dropped(), 0u);
  EXPECT_EQ(s.bytes(), 50 * (exact_bytes(10) + sizeof(KeptCloud)));
}

TEST(KeyframeStore, BudgetCountsTheMemoryCloudsHoldAndStoredCloudsHoldNoSpare) {
  // 100 push_backs leave spare capacity (vector growth); the budget is about memory, so the
  // count is by capacity, and a stored cloud is shrunk to its 100 points: 1,500 bytes.
  const mapping::LabeledCloud built = cloud_of(100);
  ASSERT_GT(built.points.capacity(), built.points.size());
  EXPECT_GT(cloud_bytes(built), exact_bytes(100));
  KeyframeStore s;
  s.note_keyframe(0, at(0));
  s.add(0, at(0), 0, cloud_of(100));
  EXPECT_EQ(cloud_bytes(s.clouds().front().cloud), 1500u);
  EXPECT_EQ(s.bytes(), 1500 + sizeof(KeptCloud));
}

TEST(KeyframeStore, DetachedKeyframesJoinTheWorldWhenACorrectionListsThem) {
  // Keyframe 2 is in a SLAM sub-map of its own (pose in that sub-map's frame): kept, not in the world.
  KeyframeStore s;
  s.note_keyframe(0, at(0));
  s.note_keyframe(2, at(0), /*detached=*/true);
  s.add(0, at(0), 0, {});
  s.add(2, at(0.5), 4, {});  // rides on the detached keyframe
  EXPECT_TRUE(s.in_world(s.clouds()[0]));
  EXPECT_FALSE(s.in_world(s.clouds()[1]));
  // A loop correction of the world alone leaves it outside.
  s.update_poses({{0, at(0)}});
  EXPECT_FALSE(s.in_world(2));
  // The merge lists it in the world: its cloud comes in (an infinite shift asks for a rebuild).
  EXPECT_EQ(s.update_poses({{0, at(0)}, {2, at(3, 1)}}), std::numeric_limits<double>::infinity());
  EXPECT_TRUE(s.in_world(2));
  EXPECT_TRUE(near(s.T_w_c(s.clouds()[1]), at(3.5, 1)));
}

TEST(KeyframeStore, AnotherSubMapBecomingTheWorldSwapsWhichCloudsAreIn) {
  // Keyframe 0 is the first map's; 2 and 3 are a sub-map's (poses in its own frame).
  KeyframeStore s;
  s.note_keyframe(0, at(0));
  s.note_keyframe(2, at(0), /*detached=*/true);
  s.note_keyframe(3, at(1), /*detached=*/true);
  s.add(0, at(0), 0, {});
  s.add(2, at(0.5), 4, {});  // rides on keyframe 2, 0.5 m ahead of it
  // SLAM made the sub-map the world; 5 is one of its keyframes culled before it was noted here.
  s.set_world({{2, at(3, 1)}, {3, at(4, 1)}, {5, at(6)}});
  EXPECT_FALSE(s.in_world(0));
  EXPECT_FALSE(s.in_world(s.clouds()[0]));
  EXPECT_TRUE(s.in_world(s.clouds()[1]));
  EXPECT_TRUE(s.in_world(3));
  EXPECT_TRUE(s.in_world(5));
  EXPECT_TRUE(near(s.T_w_c(s.clouds()[1]), at(3.5, 1)));
  EXPECT_TRUE(near(s.keyframes().at(0), at(0)));  // kept as it was, outside
  // A later correction of the world alone does not bring the old map back.
  s.update_poses({{2, at(3, 1)}, {3, at(4, 1)}});
  EXPECT_FALSE(s.in_world(0));
}

TEST(KeyframeStore, RefusesAnUnknownAnchor) {
  KeyframeStore s;
  EXPECT_THROW(s.add(7, at(0), 0, {}), Error);
}

}  // namespace
}  // namespace s3m::pipeline
