// Pose alignment used to put the ground-truth voxel map into the map's frame.
#include <gtest/gtest.h>

#include "s3m/core/error.hpp"
#include "s3m/run/evaluation.hpp"

namespace s3m::run {
namespace {

TEST(AlignPoses, RecoversTheTransformFromAStraightFlight) {
  // A straight path: positions alone cannot fix the rotation about the path; whole poses can.
  const SE3 T_est_gt =
      make_se3(Vec3(0.5, -1.0, 2.0), Quat(Eigen::AngleAxisd(0.7, Vec3(1, 2, 3).normalized())));
  std::vector<SE3> gt, est;
  for (int i = 0; i < 10; ++i) {
    gt.push_back(make_se3(Vec3(0.1 * i, 0, 1), Quat(Eigen::AngleAxisd(0.05 * i, Vec3::UnitZ()))));
    est.push_back(T_est_gt * gt.back());
  }
  const SE3 T = align_poses(est, gt);
  EXPECT_LT((T.matrix() - T_est_gt.matrix()).cwiseAbs().maxCoeff(), 1e-9);
  EXPECT_THROW(align_poses({}, {}), Error);
}

}  // namespace
}  // namespace s3m::run
