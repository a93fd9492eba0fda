// Loop closing and relocalisation through `s3m run` (run_dataset, --deterministic) on the
// simulator's loop flight with an outage: ten frames with a black colour image
// (depth kept) are LOST, marked in metrics.json, left out of the trajectory and of the map, and
// the first frame after the 1 s gap is posed again (with depth odometry off); with it on they are
// ODOMETRY: in the trajectory at the poses their depth gives, still left out of the map.
// Whether the resume frame is re-found by tracking (OK) or by relocalisation (RELOCALISED), and
// whether depth odometry or tracking poses it, differs between x86-64 machines (the last bits of
// the rendered depth), so these tests accept either and bound the result instead.
#include <cmath>
#include <cstdio>
#include <set>

#include <nlohmann/json.hpp>

#include "pipeline_fixture.hpp"
#include "s3m/io/trajectory.hpp"
#include "slam_loop_sim_fixture.hpp"

namespace s3m::it {
namespace {

// depth_odometry false: slam.tracker.odometry_frames 0, so that frames features lose are LOST.
run::RunResult run_loop(const std::string& name, Variant variant, int pixel_stride = 2,
                        bool depth_odometry = true) {
  run::RunOptions o;
  o.dataset_dir = loop_sequence_dir(variant);
  o.out_dir = (scratch_dir() / name).string();
  fs::remove_all(o.out_dir);
  o.config = sim_preset();  // loop closing and relocalisation on, shipped vocabulary
  // One thread: threaded SLAM's keyframe timing depends on the machine's load (on a loaded 2-core
  // machine it can lose the fast part of the flight), and these tests count LOST frames exactly.
  o.config.threads.deterministic = true;
  o.config.cloud.pixel_stride = pixel_stride;
  if (!depth_odometry) o.config.slam.tracker.dead_reckoning.odometry_frames = 0;
  o.segmenter = "oracle";
  o.report = false;
  return run::run_dataset(o);
}

// The loop is closed inside SLAM and its correction reaches the pipeline, which rebuilds the map.
TEST(PipelineLoopClosing, LoopCorrectionReachesTheMap) {
  const run::RunResult r = run_loop("loop_clean", Variant::kClean);
  const auto& m = r.metrics;
  std::printf("clean loop flight: ATE %.4f m, corrections %d, rebuilds %d, map mIoU %.3f, tracking %s\n",
              m["trajectory"]["ate_rmse_m"].get<double>(), m["corrections"].get<int>(),
              m["map"]["rebuilds"].get<int>(), m["map"]["miou"].get<double>(), m["tracking"].dump().c_str());
  EXPECT_EQ(m["inputs"]["poses"].get<std::string>(), "s3m SLAM + loop closing");
  EXPECT_EQ(m["tracking"]["lost_frames"].size(), 0u);
  EXPECT_EQ(m["tracking"]["states"]["OK"].get<int>(), kLoopFrames);
  EXPECT_EQ(m["tracking"]["rolling_shutter_s"].get<double>(), 0.0);  // the flight's camera.yaml has none
  EXPECT_GE(m["corrections"].get<int>(), 1);
  EXPECT_GE(m["map"]["rebuilds"].get<int>(), 2);  // after the loop correction, and the final one
  // The SLAM-level test measures 0.070 m without loop closing on this flight, 0.051 m with it.
  EXPECT_LT(m["trajectory"]["ate_rmse_m"].get<double>(), 0.06);
}

// The black frames keep their depth, which depth odometry would pose (next test): off here, as
// for a camera whose depth fails with its colour.
TEST(PipelineLoopClosing, LostFramesAreMarkedNotMappedAndTrackingResumes) {
  // Every 4th pixel is enough to see a misplaced cloud, and keeps the two runs fast.
  const run::RunResult outage = run_loop("loop_outage", Variant::kOutage, 4, /*depth_odometry=*/false);
  const run::RunResult gap = run_loop("loop_gap", Variant::kGap, 4);
  const auto& m = outage.metrics;
  std::printf(
      "outage: ATE %.4f m, map voxels %zu mIoU %.4f precision %.4f, tracking %s | same frames missing: "
      "ATE %.4f m, voxels %zu mIoU %.4f precision %.4f, tracking %s\n",
      m["trajectory"]["ate_rmse_m"].get<double>(), m["map"]["voxels"].get<std::size_t>(),
      m["map"]["miou"].get<double>(), m["map"]["precision"].get<double>(), m["tracking"].dump().c_str(),
      gap.metrics["trajectory"]["ate_rmse_m"].get<double>(), gap.metrics["map"]["voxels"].get<std::size_t>(),
      gap.metrics["map"]["miou"].get<double>(), gap.metrics["map"]["precision"].get<double>(),
      gap.metrics["tracking"].dump().c_str());
  // 1. Exactly the ten black frames are LOST (dataset positions 250..259); the first frame after
  //    the gap (position 260 = simulator frame 280) is posed again, by tracking or relocalisation.
  const int delivered = kLoopFrames - kSkipped;
  const auto& t = m["tracking"];
  ASSERT_EQ(t["lost_frames"].size(), 1u) << t.dump();
  EXPECT_EQ(t["lost_frames"][0][0].get<int>(), kBlankFirst);
  EXPECT_EQ(t["lost_frames"][0][1].get<int>(), kBlankFirst + 9);
  EXPECT_EQ(t["states"]["LOST"].get<int>(), 10);
  EXPECT_LE(t["relocalised_frames"].size(), 1u) << t.dump();
  for (const auto& f : t["relocalised_frames"]) EXPECT_EQ(f.get<int>(), kBlankFirst + 10) << t.dump();
  // 2. LOST frames are neither in the map (every other frame is: integrate = all_frames) nor in
  //    the trajectory file.
  EXPECT_EQ(m["frames"].get<int>(), delivered);
  EXPECT_EQ(m["tracked"].get<int>(), delivered - 10);
  EXPECT_EQ(m["integrated"].get<int>(), delivered - 10);
  const auto traj = io::read_tum_trajectory(m["outputs"]["trajectory_camera"].get<std::string>());
  EXPECT_EQ(traj.size(), std::size_t(delivered - 10));
  const sim::Simulation& sim = loop_simulation();
  std::set<long> lost_stamps;
  for (int i = kBlankFirst; i < kBlankFirst + 10; ++i)
    lost_stamps.insert(std::lround(sim.trajectory().samples[std::size_t(i)].t_s * 1e4));
  for (const auto& p : traj)
    EXPECT_FALSE(lost_stamps.count(std::lround(p.t_s * 1e4))) << "LOST frame at " << p.t_s;
  // 3. The map's geometry matches the one built when those frames never arrived: their depth (with
  //    a stale pose) never went in, and the later frames were put where they belong. The two runs
  //    re-find the camera on their own (a LOST stretch and a plain gap are handled differently),
  //    so their maps agree within what the resume frames' poses explain, not to the bit (identical
  //    where both take the same path); depth at a stale pose would add voxels off the surfaces.
  EXPECT_LT(m["trajectory"]["ate_rmse_m"].get<double>(), kMaxAteWithOutage_m);
  EXPECT_NEAR(m["trajectory"]["ate_rmse_m"].get<double>(),
              gap.metrics["trajectory"]["ate_rmse_m"].get<double>(), 0.005);
  const double voxels = double(m["map"]["voxels"].get<std::size_t>());
  EXPECT_NEAR(voxels / double(gap.metrics["map"]["voxels"].get<std::size_t>()), 1.0, 0.005);
  EXPECT_NEAR(m["map"]["precision"].get<double>(), gap.metrics["map"]["precision"].get<double>(), 0.002);
  // (Labels, hence mIoU, differ slightly: the oracle's noise is seeded by the frame's position.)
}

// With depth odometry (the default) the same black frames are posed by their depth: ODOMETRY,
// in the trajectory, and still not in the map (their colour is what failed). Frame 260, the first
// in colour again after the skipped frames, is posed by whichever of tracking and depth odometry
// holds there (machine-dependent, see the top): ODOMETRY, OK or RELOCALISED, never LOST.
TEST(PipelineLoopClosing, BlackFramesWithDepthArePosedByDepthOdometryButNotMapped) {
  const run::RunResult r = run_loop("loop_outage_odometry", Variant::kOutage, 4);
  const auto& m = r.metrics;
  const auto& t = m["tracking"];
  std::printf("outage with depth odometry: ATE %.4f m, tracking %s\n",
              m["trajectory"]["ate_rmse_m"].get<double>(), t.dump().c_str());
  const int delivered = kLoopFrames - kSkipped;
  const int odometry = t["states"].value("ODOMETRY", 0);
  EXPECT_TRUE(odometry == 10 || odometry == 11) << t.dump();
  EXPECT_EQ(t["states"].value("LOST", 0), 0) << t.dump();
  EXPECT_EQ(t["states"].value("OK", 0) + odometry + t["states"].value("RELOCALISED", 0), delivered)
      << t.dump();
  EXPECT_EQ(m["tracked"].get<int>(), delivered - 10);
  EXPECT_EQ(m["integrated"].get<int>(), delivered - 10);
  const auto traj = io::read_tum_trajectory(m["outputs"]["trajectory_camera"].get<std::string>());
  EXPECT_EQ(traj.size(), std::size_t(delivered));
  // ATE over every frame, the black ones included (without the odometry, over the others: 1.1 cm).
  EXPECT_LT(m["trajectory"]["ate_rmse_m"].get<double>(), 0.03);
}

}  // namespace
}  // namespace s3m::it
