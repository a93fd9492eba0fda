// Kept clouds follow keyframe corrections, including keyframes SLAM has culled since.
#include <gtest/gtest.h>

#include "s3m/core/error.hpp"
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

TEST(KeyframeStore, RefusesAnUnknownAnchor) {
  KeyframeStore s;
  EXPECT_THROW(s.add(7, at(0), 0, {}), Error);
}

}  // namespace
}  // namespace s3m::pipeline
