// End to end on the rendered textured room (fixed seeds): a full loop around the room where loop
// closing must reduce the drift, and 10 blank frames that only relocalisation recovers from.
#include <gtest/gtest.h>

#include <cstdio>
#include <set>
#include <vector>

#include "s3m/features/bow_vocabulary.hpp"
#include "s3m/slam/system.hpp"
#include "slam_synthetic_room.hpp"

namespace s3m::slam {
namespace {

constexpr int kLoopFrames = 240;  // one lap of the ellipse
constexpr int kFrames = 300;      // a lap and a quarter: the start is revisited

using test::room_camera;

// 1 % depth noise makes odometry drift by centimetres over the lap, which loop closing removes.
constexpr double kDepthNoise = 0.01;

// The SLAM's depth model told about that noise, as a preset for such a sensor would:
// sigma_z = 1 mm + 0.005 z^2 is 0.6-1.3 x the rendered 1 % of z over the room's 1-3 m. With the
// Kinect-class default (1.5e-3 z^2, 3-4x too small here) most depth rows fail the chi2 gate, few
// points count as tracked and tracking makes a keyframe nearly every frame (122 instead of ~35
// over the lap, 6x the run time; docs/RESULTS.md issue 20).
SlamConfig room_slam_config() {
  SlamConfig cfg;
  cfg.features.depth_noise.k_per_m = 0.005;
  return cfg;
}

const std::vector<RgbdFrame>& room_frames() {
  static const std::vector<RgbdFrame> frames = [] {
    std::vector<RgbdFrame> v;
    for (int i = 0; i < kFrames; ++i)
      v.push_back(test::render_room(test::Room{}, room_camera(), test::uav_pose(i, kLoopFrames), i, i / 30.0,
                                    kDepthNoise));
    return v;
  }();
  return frames;
}

// Black images for a frame copied from room_frames(). The copy shares the cached frame's pixels,
// and `f.rgb = cv::Mat::zeros(...)` would write the zeros into them (a MatExpr assigned to a Mat
// of the same size and type reuses its buffer), blanking the cached frame for every later test in
// the process; so each image gets a buffer of its own.
void blank_out(RgbdFrame& f) {
  f.rgb = cv::Mat(f.rgb.size(), f.rgb.type(), cv::Scalar::all(0));
  f.depth_m = cv::Mat(f.depth_m.size(), f.depth_m.type(), cv::Scalar::all(0));
}

std::shared_ptr<const features::Vocabulary> vocabulary() {
  static const auto v = std::make_shared<const features::Vocabulary>(
      features::Vocabulary::load(features::default_vocabulary_path()));
  return v;
}

struct RunResult {
  std::vector<FramePose> traj;
  std::vector<FrameState> states;
  int loops = 0, relocalisations = 0, corrections_heard = 0;
  size_t keyframes_in_last_correction = 0;
};

RunResult run(bool loop_closing, const std::set<int>& blank = {}) {
  SlamConfig cfg = room_slam_config();
  cfg.loop_closing.enabled = loop_closing;
  System slam(room_camera(), cfg, vocabulary());
  RunResult r;
  auto hear = [&](const std::vector<LoopCorrection>& corrections) {
    for (const auto& c : corrections) {
      ++r.corrections_heard;
      r.keyframes_in_last_correction = c.T_w_kf_after.size();
    }
  };
  for (const auto& frame : room_frames()) {
    RgbdFrame f = frame;
    if (blank.count(f.index)) blank_out(f);
    const TrackResult t = slam.track(f);
    r.states.push_back(t.state);
    hear(t.corrections);
  }
  slam.finish();
  hear(slam.late_corrections());
  r.traj = slam.camera_trajectory();
  r.loops = slam.n_loops();
  r.relocalisations = slam.n_relocalised_frames();
  return r;
}

// Camera position RMSE against ground truth in the first camera's frame (the SLAM world), so no
// alignment hides the drift; frames marked LOST are left out.
double ate_rmse(const std::vector<FramePose>& traj) {
  const SE3 T_0_w = test::uav_pose(0, kLoopFrames).inverse();
  double s = 0;
  int n = 0;
  for (const auto& p : traj) {
    if (p.state == FrameState::kLost) continue;
    const SE3 gt = T_0_w * test::uav_pose(p.frame_index, kLoopFrames);
    s += (p.T_w_x.translation() - gt.translation()).squaredNorm();
    ++n;
  }
  return std::sqrt(s / std::max(n, 1));
}

TEST(LoopClosing, ClosingTheRoomLoopReducesDrift) {
  const RunResult without = run(false);
  const RunResult with = run(true);
  const double ate_without = ate_rmse(without.traj), ate_with = ate_rmse(with.traj);
  std::printf("ATE without loop closing %.4f m, with %.4f m (%d loops)\n", ate_without, ate_with, with.loops);
  EXPECT_EQ(without.loops, 0);
  ASSERT_GE(with.loops, 1);
  EXPECT_EQ(with.corrections_heard, with.loops);  // every closure reached the caller
  EXPECT_GT(with.keyframes_in_last_correction, 10U);
  EXPECT_LT(ate_with, 0.8 * ate_without);
  // The world is the first keyframe's: closing the loop must not move it. Local BA once moved it
  // in a window with held neighbours (session 20: frame 0 ended 9 mm / 0.16 deg off, ATE 1.31 cm).
  ASSERT_EQ(with.traj.front().frame_index, 0);
  EXPECT_LT(with.traj.front().T_w_x.translation().norm(), 1e-9);
  EXPECT_LT(rotation_angle_rad(with.traj.front().T_w_x.linear()), 1e-9);
}

// The blank frames fall where the second lap passes the start again, so the camera comes back
// (22 cm and 15 deg further on) over mapped ground: motion-model tracking has nothing to go on.
// Either the tracker's own matching against its reference keyframe finds the pose (OK; since the
// inverse-depth rows of issue 20 it does, as on the kitchen in docs/RESULTS.md) or relocalisation
// against the map's keyframes does (RELOCALISED); the kidnapped camera below leaves only the latter.
// (Coming back over unmapped ground, relocalisation finds too few points and tracking resumes only
// once it is mapped.)
TEST(Relocalisation, TenBlankFramesAreMarkedLostAndTrackingRecovers) {
  std::set<int> blank;
  for (int i = 250; i < 260; ++i) blank.insert(i);
  const RunResult r = run(true, blank);
  for (int i : blank) EXPECT_EQ(r.states[size_t(i)], FrameState::kLost) << "frame " << i;
  int first_back = -1;
  for (int i = 260; i < kFrames && first_back < 0; ++i) {
    if (r.states[size_t(i)] != FrameState::kLost) first_back = i;
  }
  std::printf("tracking back at frame %d (%s), %d relocalisations, ATE %.4f m\n", first_back,
              first_back >= 0 ? to_string(r.states[size_t(first_back)]) : "-", r.relocalisations,
              ate_rmse(r.traj));
  ASSERT_GE(first_back, 260);
  EXPECT_LE(first_back, 262);
  const FrameState back = r.states[size_t(first_back)];
  EXPECT_TRUE(back == FrameState::kOk || back == FrameState::kRelocalised) << to_string(back);
  if (back == FrameState::kRelocalised) {
    EXPECT_GE(r.relocalisations, 1);
  }
  for (int i = first_back + 1; i < kFrames; ++i)
    EXPECT_NE(r.states[size_t(i)], FrameState::kLost) << "frame " << i;
  // The final trajectory has the recovered frame at its recovered pose, not the LOST guess.
  for (const auto& p : r.traj)
    if (p.frame_index == first_back) {
      EXPECT_EQ(p.state, back);
    }
  EXPECT_LT(ate_rmse(r.traj), 0.05);
}

// A kidnapped camera: 120 frames of the first lap, 10 blank frames, then the flight resumes from
// frame 40 (the camera carried ~150 deg back round the room), so the tracker's own recovery from
// its last pose cannot work and only relocalisation against the whole map can. Threaded mode runs
// relocalisation as a map query on the local-mapping thread (the sanitizer stage runs this too).
// It runs in lockstep: after each keyframe an empty map query waits until local mapping and loop
// closing have processed it, so the threads see the single-thread order of events and the exact
// expectations below hold under any load (free-running, the keyframes a loaded machine inserts
// moved the result from 1.4-3.1 cm to 5.1 cm once; free-running threads are covered by
// SlamSystem.ThreadedMode* and LoopOnSimulator.OutageIsBridgedThreadedFreeRunning).
std::vector<FramePose> expect_kidnapped_camera_relocalised(bool threaded) {
  std::vector<int> source;  // room frame shown at each step; -1: blank
  for (int i = 0; i < 120; ++i) source.push_back(i);
  for (int i = 0; i < 10; ++i) source.push_back(-1);
  for (int i = 40; i < 80; ++i) source.push_back(i);
  SlamConfig cfg = room_slam_config();
  cfg.threaded = threaded;
  System slam(room_camera(), cfg, vocabulary());
  std::vector<FrameState> states;
  for (size_t k = 0; k < source.size(); ++k) {
    RgbdFrame f = room_frames()[size_t(std::max(source[k], 0))];
    if (source[k] < 0) blank_out(f);
    f.index = int(k);
    f.t_s = double(k) / 30.0;
    const TrackResult t = slam.track(f);
    states.push_back(t.state);
    if (threaded && t.keyframe) slam.query_map([](const Map&) {});
  }
  slam.finish();
  const char* mode = threaded ? "threaded" : "single-thread";
  for (size_t k = 120; k < 130; ++k) EXPECT_EQ(states[k], FrameState::kLost) << mode << " step " << k;
  EXPECT_EQ(states[130], FrameState::kRelocalised) << mode;
  for (size_t k = 131; k < source.size(); ++k) EXPECT_EQ(states[k], FrameState::kOk) << mode << " step " << k;
  EXPECT_EQ(slam.n_relocalised_frames(), 1) << mode;
  // Where the relocalised frame ended up (final trajectory) against the ground truth of frame 40.
  const SE3 T_0_w = test::uav_pose(0, kLoopFrames).inverse();
  double worst_m = 0;
  for (const auto& p : slam.camera_trajectory()) {
    if (p.frame_index < 130) continue;
    const Vec3 gt = (T_0_w * test::uav_pose(source[size_t(p.frame_index)], kLoopFrames)).translation();
    worst_m = std::max(worst_m, (p.T_w_x.translation() - gt).norm());
    if (p.frame_index == 130) {
      EXPECT_EQ(p.state, FrameState::kRelocalised) << mode;
    }
  }
  std::printf("%s: kidnapped camera relocalised at step 130 (%s), worst position error after it %.4f m\n",
              mode, to_string(states[130]), worst_m);
  EXPECT_LT(worst_m, 0.05) << mode;
  return slam.camera_trajectory();
}

TEST(Relocalisation, KidnappedCameraIsRelocalisedSingleThread) { expect_kidnapped_camera_relocalised(false); }

TEST(Relocalisation, KidnappedCameraIsRelocalisedThreaded) {
  // In lockstep the mapping thread does exactly what single-thread mode does inline, so the two
  // trajectories must agree bit for bit: a snapshot handed over late or out of order, or a
  // relocalisation query answered against a map missing a keyframe, would show here.
  const auto threaded = expect_kidnapped_camera_relocalised(true);
  const auto single = expect_kidnapped_camera_relocalised(false);
  ASSERT_EQ(threaded.size(), single.size());
  for (std::size_t i = 0; i < single.size(); ++i) {
    EXPECT_EQ(threaded[i].frame_index, single[i].frame_index);
    EXPECT_EQ(threaded[i].state, single[i].state) << "frame " << single[i].frame_index;
    EXPECT_TRUE(threaded[i].T_w_x.isApprox(single[i].T_w_x, 0.0)) << "frame " << single[i].frame_index;
  }
}

}  // namespace
}  // namespace s3m::slam
