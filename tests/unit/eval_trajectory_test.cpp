#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "s3m/core/error.hpp"
#include "s3m/eval/trajectory_eval.hpp"

using namespace s3m;
using namespace s3m::eval;
using io::Trajectory;

namespace {

// A wavy 3D path with changing orientation, n poses at 30 Hz.
Trajectory wavy_trajectory(int n) {
  Trajectory traj;
  for (int i = 0; i < n; ++i) {
    const double t = i / 30.0;
    const Vec3 p(std::sin(0.5 * t) * 2.0, std::cos(0.3 * t) * 1.5, 0.2 * t + 0.3 * std::sin(t));
    const Vec3 phi(0.1 * std::sin(t), 0.4 * t, 0.05 * std::cos(0.7 * t));
    traj.push_back({100.0 + t, make_se3(so3_exp(phi), p)});
  }
  return traj;
}

SE3 some_rigid_transform() { return make_se3(so3_exp(Vec3(0.3, -1.2, 2.0)), Vec3(5.0, -3.0, 1.5)); }

}  // namespace

TEST(EvalStats, HandComputedValues) {
  const auto s = error_stats({3.0, 1.0, 4.0, 2.0});
  EXPECT_DOUBLE_EQ(s.mean, 2.5);
  EXPECT_DOUBLE_EQ(s.median, 2.5);
  EXPECT_DOUBLE_EQ(s.rmse, std::sqrt(30.0 / 4.0));
  EXPECT_DOUBLE_EQ(s.std, std::sqrt(1.25));  // population std
  EXPECT_DOUBLE_EQ(s.min, 1.0);
  EXPECT_DOUBLE_EQ(s.max, 4.0);
  EXPECT_DOUBLE_EQ(error_stats({5.0, 1.0, 2.0}).median, 2.0);
  EXPECT_EQ(error_stats({}).count, 0u);
}

TEST(EvalAte, RigidlyTransformedCopyHasZeroErrorWithSe3) {
  const auto gt = wavy_trajectory(300);
  Trajectory est = gt;
  const SE3 T_est_gt = some_rigid_transform();
  for (auto& p : est) p.T_w_x = T_est_gt * p.T_w_x;
  const auto ev = evaluate_trajectory(gt, est, {});
  EXPECT_EQ(ev.matched, 300u);
  EXPECT_LT(ev.ate.stats_m.rmse, 1e-9);
  EXPECT_LT(ev.ate.stats_m.max, 1e-9);
  EXPECT_LT((ev.ate.alignment.T_gt_est.matrix() - T_est_gt.inverse().matrix()).cwiseAbs().maxCoeff(), 1e-9);
  EXPECT_LT(ev.rpe.trans_m.max, 1e-9);
  EXPECT_LT(ev.rpe.rot_deg.max, 1e-6);
  // Without alignment the same copy is far off: the alignment really does the work.
  EvalOptions none;
  none.align = AlignMode::kNone;
  EXPECT_GT(evaluate_trajectory(gt, est, none).ate.stats_m.rmse, 1.0);
}

TEST(EvalAte, NoisyCopyGivesInjectedNoiseRmse) {
  const auto gt = wavy_trajectory(3000);
  Trajectory est = gt;
  std::mt19937 rng(42);
  std::normal_distribution<double> noise(0.0, 0.03);
  double sum_sq = 0;
  const SE3 T_est_gt = some_rigid_transform();
  for (auto& p : est) {
    const Vec3 n(noise(rng), noise(rng), noise(rng));
    sum_sq += n.squaredNorm();
    p.T_w_x.translation() += n;
    p.T_w_x = T_est_gt * p.T_w_x;
  }
  const double injected_rmse = std::sqrt(sum_sq / static_cast<double>(est.size()));
  const auto ev = evaluate_trajectory(gt, est, {});
  EXPECT_NEAR(ev.ate.stats_m.rmse, injected_rmse, 0.01 * injected_rmse);
  EXPECT_NEAR(ev.ate.stats_m.rmse, 0.03 * std::sqrt(3.0), 0.03 * 0.03 * std::sqrt(3.0));
}

TEST(EvalAte, Sim3RecoversKnownScale) {
  const auto gt = wavy_trajectory(200);
  Trajectory est = gt;
  const double s_gt_est = 2.5;  // estimate is 2.5x too small (monocular-style scale drift)
  const SE3 T_est_gt = some_rigid_transform();
  for (auto& p : est) {
    p.T_w_x = T_est_gt * p.T_w_x;
    p.T_w_x.translation() /= s_gt_est;
  }
  EvalOptions opt;
  opt.align = AlignMode::kSim3;
  const auto ev = evaluate_trajectory(gt, est, opt);
  EXPECT_NEAR(ev.ate.alignment.scale, s_gt_est, 1e-9);
  EXPECT_LT(ev.ate.stats_m.rmse, 1e-9);
  EXPECT_LT(ev.rpe.trans_m.max, 1e-9);  // RPE uses the recovered scale
  opt.align = AlignMode::kSe3;
  EXPECT_GT(evaluate_trajectory(gt, est, opt).ate.stats_m.rmse, 0.1);
}

TEST(EvalAte, AlignmentNeedsThreePoints) {
  EXPECT_THROW(align_positions({Vec3::Zero(), Vec3::UnitX()}, {Vec3::Zero(), Vec3::UnitX()}, AlignMode::kSe3), Error);
  EXPECT_NO_THROW(align_positions({Vec3::Zero()}, {Vec3::UnitX()}, AlignMode::kNone));
  EXPECT_THROW(parse_align_mode("affine"), Error);
}

TEST(EvalRpe, ConstantVelocityWithTranslationalDriftEqualsDrift) {
  // GT moves 1 m/s along x, the estimate 1.05 m/s: over 1 s the relative motion is 5 cm too long.
  Trajectory gt, est;
  for (int i = 0; i <= 100; ++i) {
    const double t = 0.1 * i;
    gt.push_back({t, make_se3(Mat3::Identity(), Vec3(t, 0, 0))});
    est.push_back({t, make_se3(Mat3::Identity(), Vec3(1.05 * t, 0, 0))});
  }
  EvalOptions opt;
  opt.align = AlignMode::kNone;
  auto ev = evaluate_trajectory(gt, est, opt);
  EXPECT_EQ(ev.rpe.trans_m.count, 91u);  // i = 0..90 have a pose 1 s later
  EXPECT_NEAR(ev.rpe.trans_m.rmse, 0.05, 1e-9);
  EXPECT_NEAR(ev.rpe.trans_m.min, 0.05, 1e-9);
  EXPECT_NEAR(ev.rpe.rot_deg.max, 0.0, 1e-9);
  // Frame delta: 5 frames = 0.5 s -> 2.5 cm.
  opt.rpe = {5, DeltaUnit::kFrames};
  ev = evaluate_trajectory(gt, est, opt);
  EXPECT_EQ(ev.rpe.trans_m.count, 96u);
  EXPECT_NEAR(ev.rpe.trans_m.rmse, 0.025, 1e-9);
}

TEST(EvalRpe, ConstantRotationalDriftEqualsDrift) {
  // Both turn about z while moving forward along their own x; the estimate turns 2 deg/s faster.
  Trajectory gt, est;
  const double w = 0.3, drift = 2.0 * M_PI / 180.0;
  for (int i = 0; i <= 60; ++i) {
    const double t = 0.05 * i;
    gt.push_back({t, make_se3(so3_exp(Vec3(0, 0, w * t)), Vec3(std::sin(w * t) / w, (1 - std::cos(w * t)) / w, 0))});
    est.push_back({t, make_se3(so3_exp(Vec3(0, 0, (w + drift) * t)), Vec3::Zero())});
  }
  EvalOptions opt;
  opt.align = AlignMode::kNone;
  const auto ev = evaluate_trajectory(gt, est, opt);
  EXPECT_NEAR(ev.rpe.rot_deg.rmse, 2.0, 1e-9);
  EXPECT_NEAR(ev.rpe.rot_deg.max, 2.0, 1e-9);
  // Translational RPE = the relative GT motion missing from the (stationary) estimate: chord of 1 s arc.
  EXPECT_NEAR(ev.rpe.trans_m.rmse, 2.0 * std::sin(w * 0.5) / w, 1e-9);
}

TEST(EvalAssociation, UnmatchedPosesAndTimeOffset) {
  const auto gt = wavy_trajectory(90);  // 100.0 .. 102.97 s
  Trajectory est;
  for (std::size_t i = 0; i < gt.size(); i += 3) est.push_back({gt[i].t_s + 0.015, gt[i].T_w_x});
  est.push_back({200.0, SE3::Identity()});  // no GT near: not matched, not an error
  auto ev = evaluate_trajectory(gt, est, {});
  EXPECT_EQ(ev.matched, 30u);
  EXPECT_EQ(ev.est_poses, 31u);
  EXPECT_LT(ev.ate.stats_m.rmse, 1e-9);
  EvalOptions tight;
  tight.max_dt_s = 0.01;  // 15 ms off: nothing matches -> clear error with both time ranges
  try {
    evaluate_trajectory(gt, est, tight);
    FAIL();
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("only 0 of 31"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("ground truth 100.000000"), std::string::npos) << e.what();
  }
  tight.offset_s = -0.015;  // undo the shift
  EXPECT_EQ(evaluate_trajectory(gt, est, tight).matched, 30u);
}

TEST(EvalAssociation, NothingMatchedSaysWhyWhenTheTimestampsTellIt) {
  const auto gt = wavy_trajectory(90);  // 100.0 .. 102.97 s
  const auto message = [&](const Trajectory& est, double offset_s = 0) {
    EvalOptions o;
    o.offset_s = offset_s;
    try {
      evaluate_trajectory(gt, est, o);
    } catch (const Error& e) {
      return std::string(e.what());
    }
    ADD_FAILURE() << "expected an error";
    return std::string();
  };
  Trajectory ns = gt, later = gt, far = gt;
  for (auto& p : ns) p.t_s *= 1e9;           // the same poses stamped in nanoseconds
  for (auto& p : later) p.t_s += 1000.0;     // another clock, 1000 s later
  for (std::size_t i = 0; i < far.size(); ++i) far[i].t_s = 500.0 + 100.0 * i;  // 8900 s long: not the same recording
  EXPECT_NE(message(ns).find("the estimate's timestamps look like nanoseconds"), std::string::npos) << message(ns);
  const std::string shifted = message(later);
  EXPECT_NE(shifted.find("the two clocks look -1000.000000 s apart"), std::string::npos) << shifted;
  EXPECT_NE(shifted.find("--offset"), std::string::npos) << shifted;
  EXPECT_EQ(evaluate_trajectory(gt, later, [] { EvalOptions o; o.offset_s = -1000.0; return o; }()).matched, 90u);
  const std::string unrelated = message(far);
  EXPECT_NE(unrelated.find("need at least 3"), std::string::npos) << unrelated;
  EXPECT_EQ(unrelated.find("apart"), std::string::npos) << unrelated;
  EXPECT_EQ(unrelated.find("nanoseconds"), std::string::npos) << unrelated;
}
