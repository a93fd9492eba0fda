// Ground-truth poses as a pose source: the state of each frame, and no SLAM session map to
// continue in (--poses gt --map is refused with a message that says what to use instead).
#include <string>

#include <gtest/gtest.h>

#include "s3m/core/error.hpp"
#include "s3m/pipeline/pose_source.hpp"

namespace s3m::pipeline {
namespace {

io::Trajectory straight_line() {
  io::Trajectory gt;
  for (int i = 0; i < 10; ++i) {
    SE3 T = SE3::Identity();
    T.translation().x() = 0.05 * i;
    gt.push_back({1.0 + 0.1 * i, T});
  }
  return gt;
}

RgbdFrame frame_at(int index, double t_s) {
  RgbdFrame f;
  f.index = index;
  f.t_s = t_s;
  return f;
}

TEST(GroundTruthPoses, FramesWithoutAPoseNearTheirTimeAreNoGroundTruth) {
  const auto poses = make_ground_truth_poses(straight_line());
  const TrackOutput first = poses->track(frame_at(0, 1.0));
  EXPECT_EQ(first.state, FrameState::kOk);
  EXPECT_TRUE(first.ok);
  EXPECT_TRUE(first.keyframe);
  const TrackOutput between = poses->track(frame_at(1, 1.05));  // 50 ms from either pose
  EXPECT_EQ(between.state, FrameState::kNoGroundTruth);
  EXPECT_FALSE(between.ok);
  EXPECT_EQ(poses->track(frame_at(2, 1.201)).state, FrameState::kOk);
  EXPECT_EQ(poses->camera_trajectory().size(), 2u);
}

TEST(GroundTruthPoses, HaveNoSessionMapToContinueIn) {
  const auto poses = make_ground_truth_poses(straight_line());
  EXPECT_EQ(poses->session_map(), nullptr);
  EXPECT_EQ(static_cast<const PoseSource&>(*poses).session_map(), nullptr);
  try {
    load_session_map(*poses, "run/slam_map.bin", false);
    FAIL() << "expected an error";
  } catch (const Error& e) {
    EXPECT_EQ(std::string(e.what()),
              "--map run/slam_map.bin: poses from ground truth cannot continue in a saved SLAM map "
              "(use --poses slam)");
  }
}

}  // namespace
}  // namespace s3m::pipeline
