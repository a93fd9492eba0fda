// A map that lasts (issue 23), end to end through run_dataset on two flights of one simulated
// office (session_sim_fixture.hpp): run A writes slam_map.bin; it loads and saves to the same
// bytes and relocalises every keyframe image of A; run B with --map A starts relocalised and its
// poses, in A's world with A's alignment to ground truth only, are within 2 cm; with
// --localize-only the map B saves is A's byte for byte and B makes no keyframe. Bad --map input
// stops before the first frame; an interrupted run does not overwrite the map it loaded.
#include <cmath>
#include <cstdio>
#include <filesystem>

#include <gtest/gtest.h>

#include "pipeline_fixture.hpp"
#include "s3m/core/error.hpp"
#include "s3m/eval/align.hpp"
#include "s3m/features/bow_vocabulary.hpp"
#include "s3m/io/trajectory.hpp"
#include "s3m/io/tum_dataset.hpp"
#include "s3m/pipeline/session_io.hpp"
#include "s3m/run/run.hpp"
#include "s3m/slam/io/map_io.hpp"
#include "s3m/slam/slam_config.hpp"
#include "s3m/slam/tracking/reloc.hpp"
#include "session_runs.hpp"

namespace s3m::it {
namespace {

std::string slam_map_of(const std::string& run) { return run + "/" + pipeline::kSlamMapFile; }

// Camera positions of run's trajectory against dataset's ground truth, matched by frame time.
struct Matched {
  std::vector<Vec3> est, gt;
};
Matched match(const std::string& run, const std::string& dataset) {
  const io::Trajectory est = io::read_tum_trajectory(run + "/trajectory_camera.txt");
  const io::Trajectory gt = io::read_tum_trajectory(dataset + "/groundtruth.txt");
  Matched m;
  for (const auto& p : est)
    for (const auto& g : gt)
      if (std::abs(g.t_s - p.t_s) < 1e-4) {
        m.est.push_back(p.T_w_x.translation());
        m.gt.push_back(g.T_w_x.translation());
      }
  return m;
}
double rmse(const Matched& m, const eval::Sim3& A) {
  double s = 0;
  for (std::size_t i = 0; i < m.est.size(); ++i) s += (A.apply(m.est[i]) - m.gt[i]).squaredNorm();
  return std::sqrt(s / double(std::max<std::size_t>(m.est.size(), 1)));
}
// Run A's own alignment to ground truth: the only one B's poses are judged with.
eval::Sim3 alignment_of_a() {
  const Matched a = match(run_a_dir(), flight_a_dir());
  return eval::align_positions(a.est, a.gt, eval::AlignMode::kSe3);
}

std::shared_ptr<const features::Vocabulary> vocabulary() {
  static const auto v = std::make_shared<const features::Vocabulary>(
      features::Vocabulary::load(features::default_vocabulary_path()));
  return v;
}

TEST(SessionMap, RunWritesAMapThatRoundTripsAndRelocalisesEveryKeyframeImage) {
  const io::TumDataset a = io::TumDataset::open(flight_a_dir());
  const std::string file = slam_map_of(run_a_dir());
  const slam::LoadedSlamMap m = slam::load_slam_map(file, a.camera(), vocabulary());
  EXPECT_EQ(slam::serialise_slam_map(m.map, m.index, m.loop_edges, m.camera), read_bytes(file));
  ASSERT_GE(m.map.n_keyframes(), 20);
  const slam::SlamConfig cfg;
  const features::OrbExtractor orb(cfg.features.orb);
  double worst_m = 0, worst_deg = 0;
  for (const auto& [id, kf] : m.map.keyframes()) {
    const RgbdFrame f = a.load(std::size_t(kf.frame_index));
    const auto feats = features::compute_frame_features(f.rgb, f.depth_m, a.camera(), orb, cfg.features);
    const slam::RelocResult r = slam::relocalise(feats, m.map, m.index, a.camera());
    ASSERT_TRUE(r.success) << "keyframe " << id << " (frame " << kf.frame_index << ")";
    const SE3 d = kf.T_w_c.inverse() * r.T_w_c;
    worst_m = std::max(worst_m, d.translation().norm());
    worst_deg = std::max(worst_deg, rotation_angle_rad(d.linear()) * 180.0 / M_PI);
  }
  std::printf("%d keyframes relocalised: worst %.5f m, %.4f deg\n", m.map.n_keyframes(), worst_m, worst_deg);
  EXPECT_LT(worst_m, 0.01);
  EXPECT_LT(worst_deg, 0.5);
}

TEST(SessionMap, SecondFlightContinuesInTheLoadedWorld) {
  run::RunOptions o = session_options(flight_b_dir(), (scratch_dir() / "run_b").string());
  o.map_dir = run_a_dir();
  const run::RunResult r = run::run_dataset(o);
  EXPECT_EQ(r.metrics["tracking"]["states"].value("LOST", 0), 0);
  const io::Trajectory est = io::read_tum_trajectory(o.out_dir + "/trajectory_camera.txt");
  const double ate = rmse(match(o.out_dir, flight_b_dir()), alignment_of_a());
  std::printf(
      "run B with --map A: %zu poses, %d keyframes added, ATE with A's alignment %.4f m "
      "(A's own %.4f m)\n",
      est.size(), r.metrics.value("keyframes", 0), ate,
      rmse(match(run_a_dir(), flight_a_dir()), alignment_of_a()));
  EXPECT_EQ(est.size(), io::TumDataset::open(flight_b_dir()).size());
  EXPECT_LE(ate, 0.02);
}

TEST(SessionMap, LocalizeOnlyLeavesTheMapUnchangedAndAddsNoKeyframe) {
  run::RunOptions o = session_options(flight_b_dir(), (scratch_dir() / "run_b_localized").string());
  o.map_dir = run_a_dir();
  o.localize_only = true;
  const std::string before = read_bytes(slam_map_of(run_a_dir()));
  const run::RunResult r = run::run_dataset(o);
  EXPECT_EQ(r.metrics.value("keyframes", -1), 0);
  EXPECT_EQ(read_bytes(slam_map_of(run_a_dir())), before);
  EXPECT_EQ(read_bytes(slam_map_of(o.out_dir)), before)
      << "the frozen map saves to the bytes it was loaded from";
  const double ate = rmse(match(o.out_dir, flight_b_dir()), alignment_of_a());
  std::printf("run B --localize-only: %d RELOCALISED, %d LOST, ATE with A's alignment %.4f m\n",
              r.metrics["tracking"]["states"].value("RELOCALISED", 0),
              r.metrics["tracking"]["states"].value("LOST", 0), ate);
  EXPECT_LE(ate, 0.02);
}

TEST(SessionMap, BadMapInputStopsBeforeTheFirstFrame) {
  run::RunOptions o = session_options(flight_b_dir(), (scratch_dir() / "run_bad").string());
  o.map_dir = (scratch_dir() / "no_such_run").string();
  try {
    run::run_dataset(o);
    ADD_FAILURE() << "a missing map must stop the run";
  } catch (const ParseError& e) {
    EXPECT_NE(std::string(e.what()).find("no_such_run/slam_map.bin: no such SLAM map file"),
              std::string::npos)
        << e.what();
  }
  EXPECT_FALSE(fs::exists(o.out_dir)) << "nothing was written";
  o.map_dir.clear();
  o.localize_only = true;
  EXPECT_THROW(run::run_dataset(o), Error);
}

TEST(SessionMap, InterruptedRunDoesNotOverwriteTheMapItLoaded) {
  const fs::path dir = scratch_dir() / "same_folder";
  fs::remove_all(dir);
  fs::copy(run_a_dir(), dir, fs::copy_options::recursive);
  const std::string before = read_bytes((dir / pipeline::kSlamMapFile).string());
  run::RunOptions o = session_options(flight_b_dir(), dir.string());
  o.map_dir = dir.string();
  o.stop_after_frames = 20;
  EXPECT_TRUE(run::run_dataset(o).interrupted);
  EXPECT_EQ(read_bytes((dir / pipeline::kSlamMapFile).string()), before);
  o.stop_after_frames = -1;
  o.max_frames = 30;  // a run that finishes may replace it (the user asked for the same folder)
  EXPECT_FALSE(run::run_dataset(o).interrupted);
  EXPECT_NE(read_bytes((dir / pipeline::kSlamMapFile).string()), before);
}

}  // namespace
}  // namespace s3m::it
