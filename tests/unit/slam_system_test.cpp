// End to end on a rendered textured room (fixed seeds): trajectory against ground truth in
// single-thread and threaded mode, determinism, the robot-frame calibration, config loading.
#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <filesystem>
#include <thread>

#include <gtest/gtest.h>

#include "s3m/core/error.hpp"
#include "s3m/slam/system.hpp"
#include "slam_synthetic_room.hpp"

namespace s3m::slam {
namespace {

constexpr int kFrames = 120;

using test::room_camera;

// Renders lazily and caches: each test process renders only the frames it uses.
const std::vector<RgbdFrame>& room_frames(int count = kFrames) {
  static std::vector<RgbdFrame> frames;
  for (int i = static_cast<int>(frames.size()); i < count; ++i)
    frames.push_back(
        test::render_room(test::Room{}, room_camera(), test::uav_pose(i, 2 * kFrames), i, i / 30.0, 0.002));
  return frames;
}

struct RunResult {
  std::vector<FramePose> traj;
  std::vector<TrackResult> results;
  int lost = 0, keyframes = 0;
};

// progress (optional): set to the number of frames tracked so far, for observers that pace mapping.
RunResult run(const SlamConfig& cfg, MappingObserver observer = {}, std::atomic<int>* progress = nullptr) {
  System slam(room_camera(), cfg, nullptr, std::move(observer));
  RunResult r;
  for (const auto& f : room_frames()) {
    r.results.push_back(slam.track(f));
    r.lost += r.results.back().state != FrameState::kOk;
    if (progress) progress->store(static_cast<int>(r.results.size()));
  }
  slam.finish();
  r.traj = slam.camera_trajectory();
  r.keyframes = slam.map().n_keyframes();
  return r;
}

// RMSE of camera positions against ground truth expressed in the first camera's frame (the
// SLAM world), so no alignment can hide errors.
double ate_rmse(const std::vector<FramePose>& traj) {
  const SE3 T_0_w = test::uav_pose(0, 2 * kFrames).inverse();
  double s = 0;
  for (const auto& p : traj) {
    const SE3 gt = T_0_w * test::uav_pose(p.frame_index, 2 * kFrames);
    s += (p.T_w_x.translation() - gt.translation()).squaredNorm();
  }
  return std::sqrt(s / traj.size());
}

TEST(SlamSystem, SingleThreadTracksRoomFlightDeterministically) {
  const RunResult a = run(SlamConfig{});
  ASSERT_EQ(a.traj.size(), static_cast<std::size_t>(kFrames));
  EXPECT_EQ(a.lost, 0);
  EXPECT_GE(a.keyframes, 3);
  EXPECT_LT(ate_rmse(a.traj), 0.02);
  const RunResult b = run(SlamConfig{});
  ASSERT_EQ(a.traj.size(), b.traj.size());
  for (std::size_t i = 0; i < a.traj.size(); ++i) EXPECT_TRUE(a.traj[i].T_w_x.isApprox(b.traj[i].T_w_x, 0.0));
}

TEST(SlamSystem, FinalGlobalBaRefinesTheMap) {
  // Exact intrinsics and 2 mm depth noise: one joint BA over all keyframes (the default) must not
  // make the trajectory worse than local BA alone left it, and it must actually move the keyframes.
  SlamConfig off;
  off.mapper.final_global_ba = false;
  const RunResult a = run(off), b = run(SlamConfig{});
  ASSERT_EQ(a.traj.size(), b.traj.size());
  double moved_m = 0;
  for (std::size_t i = 0; i < a.traj.size(); ++i)
    moved_m = std::max(moved_m, (a.traj[i].T_w_x.translation() - b.traj[i].T_w_x.translation()).norm());
  EXPECT_GT(moved_m, 1e-5);
  EXPECT_LE(ate_rmse(b.traj), ate_rmse(a.traj) * 1.02 + 1e-4);
  EXPECT_LT(ate_rmse(b.traj), 0.02);
}

TEST(SlamSystem, ThreadedModeTracksRoomFlight) {
  SlamConfig cfg;
  cfg.threaded = true;
  cfg.mapping_lag_frames = 0;  // take whatever local mapping has finished (timing-dependent)
  const RunResult r = run(cfg);
  EXPECT_EQ(r.lost, 0);
  // Threaded accuracy depends on how far local mapping lags tracking, i.e. on machine load: < 3 cm
  // idle, up to 4.4 cm seen with ctest -j2 next to another CPU-bound test on 2 cores. The exact
  // accuracy claim is the single-thread test's (deterministic); this one guards the threading
  // (a mapper that never answers loses tracking; a mis-ordered snapshot shows up as > 5 cm).
  EXPECT_LT(ate_rmse(r.traj), 0.05);
}

// slam.mapping_lag_frames: what tracking takes from the mapping thread depends on frame counts
// only, not on timing. Lag 1 takes every keyframe before the next frame, exactly what the
// single-thread mode does inline: the same trajectory to the last bit. Lag 3 under a mapper that is
// slow at random (0-20 ms a keyframe, different draws per run) still gives the same trajectory twice.
TEST(SlamSystem, MappingLagMakesThreadedModeDeterministic) {
  const RunResult single = run(SlamConfig{});
  SlamConfig lag1;
  lag1.threaded = true;
  EXPECT_EQ(lag1.mapping_lag_frames, 1) << "the default";
  const RunResult a = run(lag1);
  ASSERT_EQ(a.traj.size(), single.traj.size());
  for (std::size_t i = 0; i < a.traj.size(); ++i)
    EXPECT_TRUE(a.traj[i].T_w_x.isApprox(single.traj[i].T_w_x, 0.0)) << "frame " << a.traj[i].frame_index;
  EXPECT_EQ(a.keyframes, single.keyframes);
  SlamConfig lag3 = lag1;
  lag3.mapping_lag_frames = 3;
  auto slow = [](unsigned seed) {
    return [state = seed](const Map&, KeyframeId) mutable {
      state = state * 1664525u + 1013904223u;
      std::this_thread::sleep_for(std::chrono::milliseconds(state % 21));
    };
  };
  const RunResult b = run(lag3, slow(1)), c = run(lag3, slow(2));
  EXPECT_EQ(b.lost, 0);
  ASSERT_EQ(b.traj.size(), c.traj.size());
  for (std::size_t i = 0; i < b.traj.size(); ++i)
    EXPECT_TRUE(b.traj[i].T_w_x.isApprox(c.traj[i].T_w_x, 0.0)) << "frame " << b.traj[i].frame_index;
  EXPECT_LT(ate_rmse(b.traj), 0.03);
}

TEST(SlamSystem, ThreadedModeSurvivesASlowMapper) {
  // Local mapping far behind tracking: each keyframe is finished only once tracking has gone
  // kLagFrames frames past it (~0.3 s of video for a mapping step that normally takes ~15 ms), so
  // the request queue runs full. Tracking must keep inserting the keyframes it needs and wait for
  // the map instead of getting lost. The lag is counted in frames, not milliseconds, so the
  // scenario is the same on an idle and on a heavily loaded machine (a fixed sleep made it depend
  // on how fast tracking happened to run). When tracking stops advancing it is waiting for this
  // very keyframe (first snapshot, deferred retry, full queue): then mapping goes on.
  constexpr int kLagFrames = 10;
  SlamConfig cfg;
  cfg.threaded = true;
  cfg.mapping_lag_frames = 0;  // tracking runs ahead of mapping as far as the queues allow
  // No dense keyframe links: they are measured on a third thread, which under a sanitizer on a
  // loaded 2-core machine took the CPU from tracking for over the 150 ms the pacing below waits,
  // so the mapper never got 10 frames behind (ASan run of session 17); they are not what is tested.
  cfg.mapper.dense_links.enabled = false;
  std::atomic<int> tracked{0};
  int n_paced = 0;
  // "Standing still" is relative to how long a frame takes here: under a sanitizer on a loaded
  // machine a frame took over the 150 ms this once waited, and the mapper never lagged (clean-clone
  // CI of session 30, while other jobs ran). So: three times the slowest frame seen advancing.
  int slowest_frame_ms = 50;
  const RunResult r = run(
      cfg,
      [&](const Map& map, KeyframeId kf) {
        const int target = map.keyframe(kf).frame_index + kLagFrames;
        int last = tracked.load(), still_ms = 0;
        while (tracked.load() < target && tracked.load() < kFrames && still_ms < 3 * slowest_frame_ms) {
          std::this_thread::sleep_for(std::chrono::milliseconds(5));
          const int now = tracked.load();
          if (now != last) slowest_frame_ms = std::max(slowest_frame_ms, still_ms + 5);
          still_ms = now == last ? still_ms + 5 : 0;
          last = now;
        }
        n_paced += tracked.load() >= target;
      },
      &tracked);
  EXPECT_GE(n_paced, 2) << "the mapper never lagged kLagFrames behind: the test tests nothing";
  EXPECT_EQ(r.lost, 0);
  EXPECT_LT(ate_rmse(r.traj), 0.03);
  // The frames after a keyframe see the points it will add once mapped: no keyframe bursts. When
  // they counted only the (stale) map's points, tracking asked for a keyframe on every frame until
  // the snapshot came (27 keyframes, runs of 5 consecutive frames; single-thread mode: 9).
  int run_length = 0, longest_run = 0;
  for (const auto& t : r.results) {
    run_length = t.keyframe ? run_length + 1 : 0;
    longest_run = std::max(longest_run, run_length);
  }
  EXPECT_LE(longest_run, 2);
  EXPECT_LE(r.keyframes, 12);
}

TEST(SlamTracker, FewCloseTrackedPointsMakeNoKeyframeWhileOneIsPending) {
  // The close-point rule alone decides here (a threshold no frame meets, no ratio rule): with no
  // keyframe pending the next frame becomes one; with one pending it must not, because the close
  // points it lacks are the pending keyframe's, still being created by local mapping (counting
  // them made threaded mode insert ~50 % more keyframes than single-thread mode).
  TrackerConfig tc;
  tc.close_tracked_min = 100000;
  tc.keyframe_ref_ratio = 1e-6;  // (a one-keyframe map uses 0.4: frame 2 still tracks far more)
  features::FeatureConfig fc;
  Map map;
  LocalMapper mapper(map, room_camera(), MapperConfig{});
  Tracker tracker(room_camera(), fc, tc, MapperConfig{}.min_new_points);
  const TrackerOutput first = tracker.process(room_frames(3)[0]);
  ASSERT_TRUE(first.keyframe.has_value());
  tracker.set_snapshot(std::make_shared<const LocalMapSnapshot>(
      make_snapshot(map, mapper.process(*first.keyframe), MapperConfig{}.snapshot_keyframes)));
  Tracker idle = tracker, busy = tracker;
  const TrackerOutput a = idle.process(room_frames(3)[2], /*pending_keyframes=*/0);
  const TrackerOutput b = busy.process(room_frames(3)[2], /*pending_keyframes=*/1);
  ASSERT_EQ(a.state, FrameState::kOk);
  ASSERT_EQ(b.state, FrameState::kOk);
  EXPECT_TRUE(a.keyframe.has_value());
  EXPECT_FALSE(b.keyframe.has_value());
}

TEST(SlamSystem, RobotPoseIsCameraPoseTimesCalibration) {
  // Hand computation: camera at (1, 2, 3) rotated 90 deg about z; robot 0.1 m along camera x
  // and turned -90 deg about z -> robot at (1, 2.1, 3) with identity rotation.
  const SE3 T_w_c = make_se3(Vec3(1, 2, 3), Quat(Eigen::AngleAxisd(M_PI / 2, Vec3::UnitZ())));
  const SE3 T_c_r = make_se3(Vec3(0.1, 0, 0), Quat(Eigen::AngleAxisd(-M_PI / 2, Vec3::UnitZ())));
  const SE3 T_w_r = robot_pose(T_w_c, T_c_r);
  EXPECT_TRUE(T_w_r.translation().isApprox(Vec3(1, 2.1, 3), 1e-12));
  EXPECT_TRUE(T_w_r.linear().isApprox(Mat3::Identity(), 1e-12));
  // And through the system, on every frame.
  SlamConfig cfg;
  cfg.T_c_r = T_c_r;
  System slam(room_camera(), cfg);
  for (int i = 0; i < 5; ++i) {
    const auto r = slam.track(room_frames(5)[i]);
    EXPECT_TRUE(r.T_w_r.isApprox(r.T_w_c * T_c_r, 1e-12));
  }
  slam.finish();
  const auto cam = slam.camera_trajectory(), rob = slam.robot_trajectory();
  ASSERT_EQ(cam.size(), 5u);
  for (std::size_t i = 0; i < cam.size(); ++i)
    EXPECT_TRUE(rob[i].T_w_x.isApprox(cam[i].T_w_x * T_c_r, 1e-12));
}

TEST(SlamConfig, YamlOverridesDefaultsAndRejectsTypos) {
  const auto node = YAML::Load(
      "slam:\n  threaded: true\n  features:\n    orb: {n_features: 700, n_levels: 6}\n"
      "  tracker: {min_local_inliers: 25, odometry_frames: 12, odometry_deg: 0.25, odometry_m: 0.01,\n"
      "            odometry_downsample: 4, odometry_max_depth_diff_m: 0.05, anchor_keyframes: 2,\n"
      "            odometry_max_step_m: 0.2, odometry_max_step_deg: 20,\n"
      "            odometry_gap_max_depth_diff_m: 0.25,\n"
      "            odometry_agree_fraction: 0.05, odometry_min_colour_agreement: 0.3,\n"
      "            keyframe_max_deg: 12.5, keyframe_max_m: 0, wide_match_ratio: 0}\n"
      "  mapper: {final_global_ba: false, ba: {max_local_keyframes: 12, global_iterations: 7,\n"
      "           max_keyframe_step_deg: 2.5, max_keyframe_step_m: 0.08}}\n"
      "  T_c_r: {t: [0.1, 0.0, -0.05], q: [0, 0, 0.7071067811865476, 0.7071067811865476]}\n");
  const SlamConfig c = slam_config_from_yaml(node["slam"], "test.yaml");
  EXPECT_TRUE(c.threaded);
  EXPECT_EQ(c.features.orb.n_features, 700);
  EXPECT_EQ(c.features.orb.n_levels, 6);
  EXPECT_DOUBLE_EQ(c.features.orb.scale_factor, 1.2);  // default kept
  EXPECT_EQ(c.tracker.min_local_inliers, 25);
  EXPECT_EQ(c.mapper.ba.max_local_keyframes, 12);
  EXPECT_FALSE(c.mapper.final_global_ba);  // the default is on
  EXPECT_EQ(c.mapper.ba.global_iterations, 7);
  EXPECT_EQ(c.tracker.dead_reckoning.odometry_frames, 12);
  EXPECT_DOUBLE_EQ(c.tracker.dead_reckoning.odometry_deg, 0.25);
  EXPECT_DOUBLE_EQ(c.tracker.dead_reckoning.odometry_m, 0.01);
  EXPECT_EQ(c.tracker.dead_reckoning.odometry.downsample, 4);
  EXPECT_EQ(c.tracker.anchor_keyframes, 2);
  EXPECT_DOUBLE_EQ(c.tracker.keyframe_max_deg, 12.5);
  EXPECT_DOUBLE_EQ(c.tracker.keyframe_max_m, 0.0);    // 0 = off, allowed
  EXPECT_DOUBLE_EQ(c.tracker.wide_match_ratio, 0.0);  // off, allowed
  EXPECT_DOUBLE_EQ(c.tracker.dead_reckoning.odometry.max_depth_diff_m, 0.05);
  EXPECT_DOUBLE_EQ(c.tracker.dead_reckoning.odometry.max_step_m, 0.2);
  EXPECT_DOUBLE_EQ(c.tracker.dead_reckoning.odometry.max_step_deg, 20.0);
  EXPECT_DOUBLE_EQ(c.tracker.dead_reckoning.odometry.gap_max_depth_diff_m, 0.25);
  EXPECT_DOUBLE_EQ(c.tracker.dead_reckoning.odometry_agree_fraction, 0.05);
  EXPECT_THROW(slam_config_from_yaml(YAML::Load("tracker: {odometry_agree_fraction: -0.1}"), "t.yaml"),
               ParseError);
  EXPECT_DOUBLE_EQ(c.tracker.dead_reckoning.odometry_min_colour_agreement, 0.3);
  EXPECT_THROW(slam_config_from_yaml(YAML::Load("tracker: {odometry_min_colour_agreement: 1.5}"), "t.yaml"),
               ParseError)
      << "a correlation is at most 1";
  EXPECT_THROW(slam_config_from_yaml(YAML::Load("tracker: {odometry_gap_max_depth_diff_m: 0.01}"), "t.yaml"),
               ParseError)
      << "a gap's gate narrower than the usual one";
  EXPECT_DOUBLE_EQ(c.mapper.ba.max_keyframe_step_deg, 2.5);
  EXPECT_DOUBLE_EQ(c.mapper.ba.max_keyframe_step_m, 0.08);
  EXPECT_THROW(slam_config_from_yaml(YAML::Load("tracker: {odometry_downsample: 0}"), "t.yaml"), ParseError);
  EXPECT_THROW(slam_config_from_yaml(YAML::Load("tracker: {anchor_keyframes: 0}"), "t.yaml"), ParseError);
  EXPECT_THROW(slam_config_from_yaml(YAML::Load("tracker: {keyframe_max_deg: -1}"), "t.yaml"), ParseError);
  EXPECT_THROW(slam_config_from_yaml(YAML::Load("tracker: {wide_match_ratio: 1.5}"), "t.yaml"), ParseError);
  EXPECT_THROW(slam_config_from_yaml(YAML::Load("mapper: {ba: {max_keyframe_step_deg: 0}}"), "t.yaml"),
               ParseError);
  EXPECT_TRUE(c.T_c_r.translation().isApprox(Vec3(0.1, 0, -0.05)));
  EXPECT_TRUE((c.T_c_r.linear() * Vec3::UnitX()).isApprox(Vec3::UnitY(), 1e-9));
  EXPECT_THROW(slam_config_from_yaml(YAML::Load("tracker: {min_local_inlier: 3}"), "t.yaml"), ParseError);
  EXPECT_THROW(slam_config_from_yaml(YAML::Load("features: {orb: {n_levels: 0}}"), "t.yaml"), ParseError);
  EXPECT_THROW(slam_config_from_yaml(YAML::Load("T_c_r: {q: [0, 0, 0, 2]}"), "t.yaml"), ParseError);
}

TEST(SlamConfig, QueueCapacityMustHoldEveryUnansweredKeyframe) {
  // Tracking keeps up to max_pending_keyframes + 1 keyframes unanswered plus one relocalisation
  // query in flight: smaller queues could block both threads, so such a config is refused.
  EXPECT_EQ(SlamConfig{}.queue_capacity, SlamConfig{}.tracker.max_pending_keyframes + 2);
  EXPECT_EQ(
      slam_config_from_yaml(YAML::Load("queue_capacity: 6\ntracker: {max_pending_keyframes: 4}"), "t.yaml")
          .queue_capacity,
      6);
  EXPECT_THROW(slam_config_from_yaml(YAML::Load("queue_capacity: 4"), "t.yaml"), ParseError);
  EXPECT_THROW(
      slam_config_from_yaml(YAML::Load("queue_capacity: 5\ntracker: {max_pending_keyframes: 4}"), "t.yaml"),
      ParseError);
}

}  // namespace
}  // namespace s3m::slam

namespace s3m::slam {
namespace {

TEST(SlamConfig, ShippedDefaultPresetMatchesCompiledDefaults) {
  const SlamConfig c = load_slam_config(
      (std::filesystem::path(S3M_TEST_DATA_DIR).parent_path().parent_path() / "config" / "slam_default.yaml")
          .string());
  const SlamConfig d;
  EXPECT_EQ(c.features.orb.n_features, d.features.orb.n_features);
  EXPECT_EQ(c.tracker.min_local_inliers, d.tracker.min_local_inliers);
  EXPECT_EQ(c.mapper.ba.max_local_keyframes, d.mapper.ba.max_local_keyframes);
  EXPECT_EQ(c.mapper.final_global_ba, d.mapper.final_global_ba);
  EXPECT_EQ(c.mapper.ba.global_iterations, d.mapper.ba.global_iterations);
  EXPECT_EQ(c.mapper.ba.max_keyframe_step_deg, d.mapper.ba.max_keyframe_step_deg);
  EXPECT_EQ(c.mapper.ba.max_keyframe_step_m, d.mapper.ba.max_keyframe_step_m);
  EXPECT_EQ(c.tracker.dead_reckoning.odometry_frames, d.tracker.dead_reckoning.odometry_frames);
  EXPECT_EQ(c.tracker.anchor_keyframes, d.tracker.anchor_keyframes);
  EXPECT_EQ(c.tracker.keyframe_max_deg, d.tracker.keyframe_max_deg);
  EXPECT_EQ(c.tracker.keyframe_max_m, d.tracker.keyframe_max_m);
  EXPECT_EQ(c.tracker.wide_match_ratio, d.tracker.wide_match_ratio);
  EXPECT_EQ(c.tracker.dead_reckoning.odometry_deg, d.tracker.dead_reckoning.odometry_deg);
  EXPECT_EQ(c.tracker.dead_reckoning.odometry_m, d.tracker.dead_reckoning.odometry_m);
  EXPECT_EQ(c.tracker.dead_reckoning.odometry.downsample, d.tracker.dead_reckoning.odometry.downsample);
  EXPECT_EQ(c.tracker.dead_reckoning.odometry.max_depth_diff_m,
            d.tracker.dead_reckoning.odometry.max_depth_diff_m);
  EXPECT_EQ(c.tracker.dead_reckoning.odometry.max_step_m, d.tracker.dead_reckoning.odometry.max_step_m);
  EXPECT_EQ(c.tracker.dead_reckoning.odometry.max_step_deg, d.tracker.dead_reckoning.odometry.max_step_deg);
  EXPECT_EQ(c.tracker.dead_reckoning.odometry.gap_max_depth_diff_m,
            d.tracker.dead_reckoning.odometry.gap_max_depth_diff_m);
  EXPECT_EQ(c.tracker.dead_reckoning.odometry_min_colour_agreement,
            d.tracker.dead_reckoning.odometry_min_colour_agreement);
  EXPECT_TRUE(c.T_c_r.isApprox(d.T_c_r));
  EXPECT_EQ(c.queue_capacity, d.queue_capacity);
  EXPECT_THROW(load_slam_config("/nonexistent/slam.yaml"), ParseError);
}

}  // namespace
}  // namespace s3m::slam
