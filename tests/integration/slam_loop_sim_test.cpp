// End to end on an `s3m sim` sequence (fixed seed): the `loop` flight comes back over its start,
// so loop closing must reduce the drift; after an outage (10 blank frames, then a 1 s gap) on the
// way back, the camera must be found again, with the blank frames marked LOST. The outage is run
// single-thread, threaded in lockstep and threaded free-running (what holds whatever the load).
// Which component finds the camera after the gap is not asserted: whether the tracker's own
// reference-keyframe search holds (OK) or relocalisation is needed (RELOCALISED) turns on the last
// bits of the rendered depth and of the solvers, which differ between x86-64 machines (Embree picks
// its kernels by the CPU's vector width). What must hold anywhere is asserted: the blank frames are
// LOST, the resume frame is posed within a bound of the truth by one of the two, and nothing else is
// lost. Relocalisation itself is asserted exactly where only it can work (the kidnapped camera in
// tests/unit/slam_loop_closing_test.cpp).
#include <cmath>
#include <cstdio>
#include <map>

#include <gtest/gtest.h>

#include "s3m/core/se3.hpp"
#include "s3m/eval/trajectory_eval.hpp"
#include "s3m/features/bow_vocabulary.hpp"
#include "s3m/slam/system.hpp"
#include "slam_loop_sim_fixture.hpp"

namespace s3m::it {
namespace {

std::shared_ptr<const features::Vocabulary> vocabulary() {
  static const auto v = std::make_shared<const features::Vocabulary>(
      features::Vocabulary::load(features::default_vocabulary_path()));
  return v;
}

struct LoopRun {
  std::vector<slam::FramePose> traj;
  std::map<int, FrameState> states;  // by frame index (= simulator frame)
  int loops = 0, relocalisations = 0, corrections_heard = 0;
};

// kLockstep: threaded SLAM, but after each keyframe tracking waits until local mapping and loop
// closing have processed it (an empty map query is a barrier: it queues behind the keyframe and
// returns once its snapshot reached the tracker). The mapping-thread code paths run with the
// single-thread order of events, so the outcome does not depend on the machine's load.
// kFree: threaded as in production; keyframe timing, and with it the result, depends on load.
enum class Mode { kSingleThread, kLockstep, kFree };

const char* to_string(Mode m) {
  return m == Mode::kSingleThread ? "single-thread"
         : m == Mode::kLockstep   ? "threaded lockstep"
                                  : "threaded free";
}

LoopRun run(bool loop_closing, Mode mode, bool outage) {
  const io::TumDataset& data = loop_dataset();
  slam::SlamConfig cfg;
  cfg.threaded = mode != Mode::kSingleThread;
  cfg.T_c_r = loop_simulation().trajectory().T_c_r;
  cfg.loop_closing.enabled = loop_closing;
  slam::System slam(data.camera(), cfg, vocabulary());
  LoopRun r;
  for (std::size_t i = 0; i < data.size(); ++i) {
    if (outage && !delivered_in_outage(int(i))) continue;
    RgbdFrame f = data.load(i);
    if (outage && int(i) >= kBlankFirst && int(i) < kBlankFirst + 10) {
      f.rgb.setTo(0);
      f.depth_m.setTo(0);
    }
    const slam::TrackResult t = slam.track(f);
    r.states[f.index] = t.state;
    r.corrections_heard += int(t.corrections.size());
    if (mode == Mode::kLockstep && t.keyframe) slam.query_map([](const slam::Map&) {});
  }
  slam.finish();
  r.corrections_heard += int(slam.late_corrections().size());
  r.traj = slam.camera_trajectory();
  r.loops = slam.n_loops();
  r.relocalisations = slam.n_relocalised_frames();
  return r;
}

// Camera position RMSE after SE3 alignment (TUM's ATE) over the frames SLAM did not mark LOST.
double ate_rmse(const std::vector<slam::FramePose>& traj) {
  const auto& gt_poses = loop_simulation().trajectory().samples;
  eval::MatchedPoses matched;
  for (const auto& p : traj) {
    if (p.state == FrameState::kLost) continue;
    matched.t_s.push_back(p.t_s);
    matched.T_w_est.push_back(p.T_w_x);
    matched.T_w_gt.push_back(gt_poses[std::size_t(p.frame_index)].T_w_c);
  }
  return eval::compute_ate(matched, eval::AlignMode::kSe3).stats_m.rmse;
}

TEST(LoopOnSimulator, LoopClosingReducesAteOnTheLoopFlight) {
  const LoopRun without = run(false, Mode::kSingleThread, false);
  const LoopRun with = run(true, Mode::kSingleThread, false);
  const double ate_without = ate_rmse(without.traj), ate_with = ate_rmse(with.traj);
  std::printf("sim loop flight: ATE without loop closing %.4f m, with %.4f m (%d loops)\n", ate_without,
              ate_with, with.loops);
  EXPECT_EQ(without.loops, 0);
  ASSERT_GE(with.loops, 1);
  EXPECT_EQ(with.corrections_heard, with.loops);
  for (const auto& [i, s] : with.states) EXPECT_EQ(s, FrameState::kOk) << "frame " << i;
  EXPECT_LT(ate_with, 0.85 * ate_without);
}

// Motion from the last frame before the outage to frame `to`, as estimated and as true: the error
// of the re-found pose, independent of the drift accumulated before the outage.
struct StepError {
  double deg = 0, m = 0;
};
StepError resume_step_error(const std::vector<slam::FramePose>& traj, int to) {
  const auto& gt = loop_simulation().trajectory().samples;
  const int from = kBlankFirst - 1;
  const slam::FramePose* a = nullptr;
  const slam::FramePose* b = nullptr;
  for (const auto& p : traj) {
    if (p.frame_index == from) a = &p;
    if (p.frame_index == to) b = &p;
  }
  if (!a || !b) return {1e9, 1e9};
  const SE3 est = a->T_w_x.inverse() * b->T_w_x;
  const SE3 truth = gt[std::size_t(from)].T_w_c.inverse() * gt[std::size_t(to)].T_w_c;
  const SE3 err = truth.inverse() * est;
  return {rotation_angle_rad(err.rotation()) * 180.0 / M_PI, err.translation().norm()};
}

void expect_outage_bridged(Mode mode) {
  const LoopRun r = run(true, mode, true);
  const char* name = to_string(mode);
  const FrameState resume = r.states.at(kResumeSource);
  const StepError step = resume_step_error(r.traj, kResumeSource);
  std::printf(
      "%s: frame %d after the outage is %s (%.3f deg / %.4f m from the truth since frame %d), "
      "%d relocalisations, %d loops, ATE %.4f m\n",
      name, kResumeSource, to_string(resume), step.deg, step.m, kBlankFirst - 1, r.relocalisations, r.loops,
      ate_rmse(r.traj));
  // 1. Exactly the blank frames are LOST; every other frame is posed.
  int relocalised_states = 0;
  for (const auto& [i, s] : r.states) {
    const bool blank = i >= kBlankFirst && i < kBlankFirst + 10;
    EXPECT_EQ(s == FrameState::kLost, blank) << name << " frame " << i << " " << to_string(s);
    relocalised_states += s == FrameState::kRelocalised;
  }
  // 2. The resume frame is re-found by tracking or by relocalisation, and the count says which.
  EXPECT_TRUE(resume == FrameState::kOk || resume == FrameState::kRelocalised) << name;
  EXPECT_EQ(r.relocalisations, relocalised_states) << name;
  EXPECT_LE(r.relocalisations, 1) << name;
  // 3. Its pose: the 1 s of motion across the outage (~40 deg, ~1 m) within 1 deg / 3 cm of the truth.
  EXPECT_LT(step.deg, 1.0) << name;
  EXPECT_LT(step.m, 0.03) << name;
  // 4. The final trajectory keeps the LOST marks and the resume frame's state.
  int lost = 0;
  for (const auto& p : r.traj) {
    lost += p.state == FrameState::kLost;
    if (p.frame_index == kResumeSource) {
      EXPECT_EQ(p.state, resume) << name;
    }
  }
  EXPECT_EQ(lost, 10) << name;
  EXPECT_LT(ate_rmse(r.traj), kMaxAteWithOutage_m) << name;
}

TEST(LoopOnSimulator, OutageIsLostThenBridgedSingleThread) { expect_outage_bridged(Mode::kSingleThread); }
TEST(LoopOnSimulator, OutageIsLostThenBridgedThreaded) { expect_outage_bridged(Mode::kLockstep); }

TEST(LoopOnSimulator, OutageIsBridgedThreadedFreeRunning) {
  // Free-running threads, so only what holds under any load: a loaded 2-core machine may lose the
  // fast middle of the flight before the outage (relocalisation brings it back), and when mapping
  // lags, the reference keyframe the tracker holds at the resume frame may be one its own search
  // recovers from (OK) rather than relocalisation (RELOCALISED). Either way the blank frames are
  // LOST, tracking is back at the resume frame and stays back, and the trajectory has not
  // diverged. Seen: 3.0-11 cm idle and beside two busy loops, once 27.8 cm under ctest's parallel
  // load; the accuracy claim (8 cm) is the lockstep test's.
  const LoopRun r = run(true, Mode::kFree, true);
  std::printf("threaded free: frame %d after the outage is %s, %d relocalisations, %d loops, ATE %.4f m\n",
              kResumeSource, to_string(r.states.at(kResumeSource)), r.relocalisations, r.loops,
              ate_rmse(r.traj));
  for (int i = kBlankFirst; i < kBlankFirst + 10; ++i) EXPECT_EQ(r.states.at(i), FrameState::kLost) << i;
  for (const auto& [i, s] : r.states) {
    if (i >= kResumeSource) {
      EXPECT_NE(s, FrameState::kLost) << "frame " << i;
    }
  }
  EXPECT_LT(ate_rmse(r.traj), 0.4);  // a wrong relocalisation or a corrupted map is off by metres
}

}  // namespace
}  // namespace s3m::it
