// Tracking failure through the whole pipeline (SLAM + oracle segmentation + semantic map) on a short
// simulated hand-held sequence (fixed seed), rendered in memory with the sim library: blank colour
// frames, depth dropouts (whole frames and image regions) and frames that never arrive. Frames while
// SLAM is LOST must not reach the map, tracking must come back, and the outputs must say which frames
// were LOST.
#include <map>
#include <set>

#include <opencv2/imgcodecs.hpp>

#include "pipeline_fixture.hpp"
#include "s3m/core/error.hpp"
#include "s3m/io/text_lines.hpp"
#include "s3m/mapping/map_io.hpp"
#include "s3m/mapping/metrics.hpp"
#include "s3m/pipeline/factories.hpp"
#include "s3m/pipeline/pipeline.hpp"
#include "s3m/semantics/oracle_segmenter.hpp"
#include "s3m/sim/gt_voxels.hpp"

namespace s3m::it {
namespace {

const auto* const kCleanup = ::testing::AddGlobalTestEnvironment(new ScratchCleanup);

// What goes wrong with a frame. kBlankRgb: the colour stream fails but depth is intact, so a
// pipeline that integrated LOST frames would put its (wrongly posed) depth into the map.
enum class Fault { kBlankRgb, kBlankAll, kNoDepth, kDepthHole };

RgbdFrame with_fault(RgbdFrame f, Fault fault) {
  switch (fault) {
    case Fault::kBlankRgb: f.rgb.setTo(0); break;
    case Fault::kBlankAll: f.rgb.setTo(0), f.depth_m.setTo(0); break;
    case Fault::kNoDepth: f.depth_m.setTo(0); break;
    case Fault::kDepthHole: f.depth_m.colRange(0, f.depth_m.cols / 2).setTo(0); break;
  }
  return f;
}

struct Scenario {
  std::map<int, Fault> faults;  // frame index -> what is wrong with it
  std::set<int> dropped;        // frames that never reach the pipeline
  bool depth_odometry = true;   // false: slam.tracker.odometry_frames 0 (what features lose is LOST)
};

constexpr int kLength = kFrames;  // the fixture's 2 s hand-held office flight, rendered in memory

const sim::Simulation& simulation() {
  static const sim::Simulation sim(sequence_config());
  return sim;
}

// Runs the simulator preset's pipeline (SLAM, noisy oracle, every tracked frame integrated) in
// deterministic mode, so that two runs differ only through their inputs.
std::unique_ptr<pipeline::Pipeline> run(const Scenario& s) {
  const sim::Simulation& sim = simulation();
  pipeline::PipelineConfig config = sim_preset();
  config.threads.deterministic = true;
  if (!s.depth_odometry) config.slam.tracker.dead_reckoning.odometry_frames = 0;
  EXPECT_EQ(config.flow.integrate, pipeline::IntegrateMode::kAllFrames);  // the strictest case
  auto p = std::make_unique<pipeline::Pipeline>(
      config, sim.camera(), pipeline::make_slam_poses(sim.camera(), config),
      std::make_unique<semantics::OracleSegmenter>(config.segmenter.oracle, config.segmenter.top_k),
      std::make_unique<pipeline::MapIntegrator>(config.map));
  for (int i = 0; i < kLength; ++i) {
    if (s.dropped.count(i)) continue;
    RgbdFrame f = sim.frame(static_cast<std::size_t>(i));
    if (auto it = s.faults.find(i); it != s.faults.end()) f = with_fault(std::move(f), it->second);
    p->process(std::move(f));
  }
  p->finish();
  return p;
}

std::string map_bytes(const pipeline::Pipeline& p, const std::string& name) {
  const std::string path = (scratch_dir() / (name + ".ot")).string();
  mapping::save_semantic_map(p.map()->tree(), path);
  return read_bytes(path);
}

// The map against the simulator's ground-truth voxels, moved into SLAM's world (the camera of
// frame 0, which starts the map).
mapping::MapEvaluation score(const pipeline::Pipeline& p) {
  const sim::Simulation& sim = simulation();
  io::GtVoxelMap gt = sim::voxelize_scene(sim.scene(), 0.05);
  const Eigen::Isometry3f T_slam_sim = sim.trajectory().samples[0].T_w_c.inverse().cast<float>();
  for (auto& c : gt.centres_w) c = T_slam_sim * c;
  return mapping::evaluate_map(p.map()->tree(), gt);
}

// Largest camera position error against the simulator's ground truth over tracked frames [m].
double max_tracked_error_m(const pipeline::Pipeline& p) {
  const auto& samples = simulation().trajectory().samples;
  const SE3 T_slam_sim = samples[0].T_w_c.inverse();
  double worst = 0;
  for (const auto& f : p.frames())
    if (f.tracked)
      worst = std::max(worst,
                       (f.T_w_c.translation() - (T_slam_sim * samples[f.index].T_w_c).translation()).norm());
  return worst;
}

// The non-comment lines of a whitespace-separated text file, split into fields.
std::vector<std::vector<std::string>> table(const std::string& path) {
  io::LineReader reader(path, "a table");
  std::vector<std::vector<std::string>> rows;
  std::vector<std::string_view> tokens;
  while (reader.next(tokens)) rows.emplace_back(tokens.begin(), tokens.end());
  return rows;
}

const pipeline::FrameOutcome& outcome(const pipeline::Pipeline& p, int index) {
  for (const auto& f : p.frames())
    if (f.index == index) return f;
  throw Error("no outcome for frame " + std::to_string(index));
}

TEST(TrackingFailure, FramesWhileLostAreNotIntegratedAndTrackingRecovers) {
  // Frames 30-34: black colour image, depth intact. SLAM cannot track them (no features). Depth
  // odometry would pose them from their depth (next test): off here, so that they are LOST.
  Scenario blank_rgb, blank_all;
  blank_rgb.depth_odometry = blank_all.depth_odometry = false;
  for (int i = 30; i < 35; ++i)
    blank_rgb.faults[i] = Fault::kBlankRgb, blank_all.faults[i] = Fault::kBlankAll;
  const auto a = run(blank_rgb);
  ASSERT_EQ(a->frames().size(), static_cast<std::size_t>(kLength));
  for (int i = 30; i < 35; ++i) {
    const auto& f = outcome(*a, i);
    EXPECT_EQ(f.state, FrameState::kLost) << "frame " << i << " " << to_string(f.state);
    EXPECT_FALSE(f.tracked) << "frame " << i;
    EXPECT_FALSE(f.integrated) << "frame " << i;
  }
  // Tracking comes back within 5 frames and holds to the end, with poses still right.
  int first_ok = -1;
  for (int i = 35; i < kLength && first_ok < 0; ++i)
    if (outcome(*a, i).tracked) first_ok = i;
  ASSERT_GE(first_ok, 35);
  EXPECT_LE(first_ok, 40);
  for (int i = first_ok; i < kLength; ++i) EXPECT_TRUE(outcome(*a, i).tracked) << "frame " << i;
  EXPECT_LT(max_tracked_error_m(*a), 0.05);
  // The LOST frames' depth never reached the map: the map is byte-identical to the one of a run whose
  // frames 30-34 had no depth at all (SLAM sees the same black images in both runs).
  const auto b = run(blank_all);
  EXPECT_EQ(b->counters().tracked, a->counters().tracked);
  EXPECT_EQ(b->counters().integrated, a->counters().integrated);
  EXPECT_TRUE(map_bytes(*a, "lost_blank_rgb") == map_bytes(*b, "lost_blank_all"))
      << "depth of LOST frames changed the map";
  // And the map is still the scene: nearly every occupied voxel lies on a ground-truth surface.
  EXPECT_GT(score(*a).precision, 0.9);
}

// With depth odometry (the default), the same black frames keep a pose from their depth: ODOMETRY,
// with the position error of tracked frames, yet not tracked and not in the map (their colour and
// labels are what failed).
TEST(TrackingFailure, BlackFramesWithDepthArePosedByOdometryAndKeptOutOfTheMap) {
  Scenario blank_rgb;
  for (int i = 30; i < 35; ++i) blank_rgb.faults[i] = Fault::kBlankRgb;
  const auto a = run(blank_rgb);
  const auto& samples = simulation().trajectory().samples;
  const SE3 T_slam_sim = samples[0].T_w_c.inverse();
  for (int i = 30; i < 35; ++i) {
    const auto& f = outcome(*a, i);
    EXPECT_EQ(f.state, FrameState::kOdometry) << "frame " << i << " " << to_string(f.state);
    EXPECT_FALSE(f.tracked) << "frame " << i;
    EXPECT_FALSE(f.integrated) << "frame " << i;
    EXPECT_LT((f.T_w_c.translation() - (T_slam_sim * samples[std::size_t(i)].T_w_c).translation()).norm(),
              0.05)
        << "frame " << i;
  }
  for (int i = 35; i < kLength; ++i) EXPECT_TRUE(outcome(*a, i).tracked) << "frame " << i;
  EXPECT_LT(max_tracked_error_m(*a), 0.05);
  EXPECT_GT(score(*a).precision, 0.9);
}

TEST(TrackingFailure, DepthDropoutsLoseNoTrackAndAddNoFalseVoxels) {
  Scenario dropouts;
  for (int i = 20; i < 25; ++i) dropouts.faults[i] = Fault::kNoDepth;    // whole frames without depth
  for (int i = 35; i < 45; ++i) dropouts.faults[i] = Fault::kDepthHole;  // left half without depth
  const auto clean = run({});
  const auto p = run(dropouts);
  // Frames without depth add nothing; the map is the scene, as precise as without dropouts.
  EXPECT_LT(p->counters().raw_points, clean->counters().raw_points);
  const mapping::MapEvaluation s = score(*p), s_clean = score(*clean);
  EXPECT_GT(s.precision, 0.9);
  EXPECT_GT(s.precision, s_clean.precision - 0.02);
  EXPECT_GT(s.recall, 0.8 * s_clean.recall);  // the rest of the sequence fills the gaps
  // Frames with depth left are tracked; so is the end of the sequence, with poses still right.
  for (int i = 35; i < 45; ++i) EXPECT_TRUE(outcome(*p, i).tracked) << "frame " << i;
  EXPECT_TRUE(p->frames().back().tracked);
  EXPECT_LT(max_tracked_error_m(*p), 0.05);
}

TEST(TrackingFailure, DroppedFramesAreSkippedAndTrackingContinues) {
  Scenario gap;
  for (int i = 25; i < 31; ++i) gap.dropped.insert(i);  // 0.2 s without frames: a larger jump
  const auto p = run(gap);
  ASSERT_EQ(p->frames().size(), static_cast<std::size_t>(kLength - 6));
  EXPECT_EQ(outcome(*p, 24).index, 24);
  EXPECT_EQ(outcome(*p, 31).index, 31);
  EXPECT_THROW(outcome(*p, 27), Error);
  int untracked_after_gap = 0;
  for (int i = 31; i < kLength; ++i) untracked_after_gap += !outcome(*p, i).tracked;
  EXPECT_LE(untracked_after_gap, 3);
  EXPECT_TRUE(p->frames().back().tracked);
  EXPECT_LT(max_tracked_error_m(*p), 0.05);
  EXPECT_GT(score(*p).precision, 0.9);
}

// Through `s3m run` (the library call): a sequence on disk whose frames 30-34 are blank. The LOST
// frames are listed as such in frames.txt and counted in metrics.json.
TEST(TrackingFailure, RunMarksLostFramesInFramesTxtAndMetrics) {
  const fs::path seq = scratch_dir() / "blank_sequence";
  fs::remove_all(seq);
  fs::copy(sequence_dir(), seq, fs::copy_options::recursive);
  // Blank the colour and depth PNGs of frames 30-34 (the same files the TUM lists name).
  const auto rgb = table((seq / "rgb.txt").string());
  const auto depth = table((seq / "depth.txt").string());
  ASSERT_EQ(rgb.size(), static_cast<std::size_t>(kFrames));
  for (int i = 30; i < 35; ++i) {
    const fs::path rgb_png = seq / rgb[i].at(1), depth_png = seq / depth[i].at(1);
    cv::Mat c = cv::imread(rgb_png.string(), cv::IMREAD_UNCHANGED),
            d = cv::imread(depth_png.string(), cv::IMREAD_UNCHANGED);
    ASSERT_FALSE(c.empty() || d.empty());
    c.setTo(0), d.setTo(0);
    ASSERT_TRUE(cv::imwrite(rgb_png.string(), c) && cv::imwrite(depth_png.string(), d));
  }
  run::RunOptions o = options("blank_run", /*deterministic=*/true);
  o.dataset_dir = seq.string();
  const auto r = run::run_dataset(o);
  const auto lines = table(o.out_dir + "/frames.txt");
  ASSERT_EQ(lines.size(), static_cast<std::size_t>(kFrames));
  for (int i = 30; i < 35; ++i) {
    EXPECT_EQ(lines[i].at(0), std::to_string(i));
    EXPECT_EQ(lines[i].at(2), "LOST") << "frame " << i;
    EXPECT_EQ(lines[i].at(3), "0");
    EXPECT_EQ(lines[i].at(5), "0");
  }
  EXPECT_EQ(lines[0].at(2), "OK");
  EXPECT_EQ(lines.back().at(2), "OK");
  EXPECT_GE(r.metrics["tracking"]["states"].value("LOST", 0), 5);
  ASSERT_FALSE(r.metrics["tracking"]["lost_frames"].empty());
  EXPECT_EQ(r.metrics["tracking"]["lost_frames"][0][0].get<int>(), 30);  // the first blank frame
  EXPECT_EQ(r.metrics["outputs"]["frames"].get<std::string>(), o.out_dir + "/frames.txt");
}

}  // namespace
}  // namespace s3m::it
