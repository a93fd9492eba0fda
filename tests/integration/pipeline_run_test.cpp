// End-to-end: `s3m run` (as a library call) on a short simulated UAV flight with the noisy oracle
// segmenter, checked against the simulator's ground truth.
#include <fstream>
#include <map>
#include <string>
#include <vector>

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include "pipeline_fixture.hpp"
#include "s3m/core/error.hpp"
#include "s3m/io/ply.hpp"
#include "s3m/io/trajectory.hpp"
#include "s3m/mapping/map_io.hpp"

namespace s3m::it {
namespace {

const auto* const kCleanup = ::testing::AddGlobalTestEnvironment(new ScratchCleanup);

// Everything `s3m run` promises to write exists and loads with the project's own readers.
void expect_loadable_outputs(const std::string& out, std::size_t frames) {
  const auto cam = io::read_tum_trajectory(out + "/trajectory_camera.txt");
  const auto robot = io::read_tum_trajectory(out + "/trajectory_robot.txt");
  const auto kfs = io::read_tum_trajectory(out + "/keyframes.txt");
  EXPECT_GT(cam.size(), frames / 2);
  EXPECT_LE(cam.size(), frames);
  ASSERT_EQ(robot.size(), cam.size());
  EXPECT_GE(kfs.size(), 2u);
  const auto map = mapping::load_semantic_map(out + "/map.ot");
  ASSERT_NE(map, nullptr);
  EXPECT_GT(map->getNumLeafNodes(), 1000u);
  const auto ply = io::read_ply(out + "/map.ply");
  EXPECT_GT(ply.size(), 1000u);
  const auto metrics = nlohmann::json::parse(read_bytes(out + "/metrics.json"));
  EXPECT_EQ(metrics["frames"].get<std::size_t>(), frames);
  EXPECT_GE(metrics["map"]["voxels"].get<std::size_t>(), ply.size());  // pruned leaves hold several voxels
}

TEST(PipelineRun, ThreadedRunWritesEveryOutputAndTracksWell) {
  run::RunOptions o = options("threaded", /*deterministic=*/false);
  const run::RunResult r = run::run_dataset(o);
  EXPECT_FALSE(r.interrupted);
  EXPECT_EQ(r.frames_done, static_cast<std::size_t>(kFrames));
  expect_loadable_outputs(o.out_dir, kFrames);

  const auto& m = r.metrics;
  // Trajectory against ground truth: the simulator's flight is easy for ORB tracking.
  ASSERT_TRUE(m["trajectory"].contains("ate_rmse_m")) << m["trajectory"].dump();
  EXPECT_LT(m["trajectory"]["ate_rmse_m"].get<double>(), 0.05);
  EXPECT_EQ(m["trajectory"]["matched"].get<std::size_t>(), m["tracked"].get<std::size_t>());
  // The robot trajectory (T_w_c * T_c_r with the preset's calibration) against the robot ground
  // truth is as accurate as the camera's: a wrong T_c_r would add its lever arm to every pose.
  ASSERT_TRUE(m["trajectory"]["robot"].contains("ate_rmse_m")) << m["trajectory"]["robot"].dump();
  EXPECT_LT(m["trajectory"]["robot"]["ate_rmse_m"].get<double>(), 0.05);
  // Every stage was timed on every frame it ran on.
  EXPECT_EQ(m["timings_ms"]["track"]["count"].get<int>(), kFrames);
  // The tracker alone, within the stage that also holds --deterministic's local mapping.
  ASSERT_TRUE(m["timings_ms"].contains("slam_tracking"));
  EXPECT_EQ(m["timings_ms"]["slam_tracking"]["count"].get<int>(), kFrames);
  EXPECT_GT(m["timings_ms"]["slam_tracking"]["mean"].get<double>(), 0.0);
  EXPECT_LE(m["timings_ms"]["slam_tracking"]["mean"].get<double>(),
            m["timings_ms"]["track"]["mean"].get<double>());
  EXPECT_EQ(m["timings_ms"]["map"]["count"].get<int>(), m["integrated"].get<int>());
  EXPECT_GT(m["map"]["raw_over_file_ratio"].get<double>(), 20.0);  // map file >= 20x smaller than raw cloud
}

TEST(PipelineRun, FusedMapBeatsSingleFrameSegmentationForEveryFusionPolicy) {
  for (const std::string policy : {"paper", "max_confidence", "bayesian"}) {
    run::RunOptions o = options("fusion_" + policy, /*deterministic=*/true);
    o.config.map.fusion.policy = mapping::parse_fusion_policy(policy);
    const auto m = run::run_dataset(o).metrics;
    ASSERT_TRUE(m["segmentation"].contains("miou")) << policy;
    ASSERT_TRUE(m["map"].contains("miou")) << policy << ": " << m["map"].dump();
    const double frame_miou = m["segmentation"]["miou"], map_miou = m["map"]["miou"];
    RecordProperty("miou_" + policy, std::to_string(frame_miou) + " -> " + std::to_string(map_miou));
    EXPECT_GT(map_miou, frame_miou) << policy;
    EXPECT_GT(m["map"]["gt_voxels_observed"].get<std::size_t>(), 1000u) << policy;
    // The same question in the images: the map's labels projected back vs the frames, same pixels.
    ASSERT_TRUE(m["map"].contains("reprojected")) << policy;
    const auto& r = m["map"]["reprojected"];
    EXPECT_GT(r["miou"].get<double>(), r["frame_miou"].get<double>()) << policy;
    EXPECT_GT(r["coverage"].get<double>(), 0.9) << policy;
    EXPECT_GE(r["frames"].get<int>(), 5) << policy;
  }
}

// With the shipped network the errors are systematic (the same object mislabelled from similar
// views), which fusion cannot out-vote in 3-D; reprojected into the frames the map must still beat them.
TEST(PipelineRun, FusedMapBeatsTheShippedNetworkInTheImagesForEveryFusionPolicy) {
  for (const std::string policy : {"paper", "max_confidence", "bayesian"}) {
    run::RunOptions o = options("net_" + policy, /*deterministic=*/true);
    o.segmenter = "onnx:" + std::string(S3M_TEST_DATA_DIR) + "/../../models/s3m_pspnet_small.yaml";
    o.config.map.fusion.policy = mapping::parse_fusion_policy(policy);
    const auto m = run::run_dataset(o).metrics;
    ASSERT_TRUE(m["map"].contains("reprojected")) << policy << ": " << m["map"].dump();
    const auto& r = m["map"]["reprojected"];
    RecordProperty("reprojected_miou_" + policy, std::to_string(r["frame_miou"].get<double>()) + " -> " +
                                                     std::to_string(r["miou"].get<double>()));
    EXPECT_GT(r["miou"].get<double>(), r["frame_miou"].get<double>()) << policy;
    EXPECT_GT(r["coverage"].get<double>(), 0.9) << policy;
  }
}

TEST(PipelineRun, DeterministicModeReproducesByteIdenticalOutputs) {
  run::RunOptions a = options("det_a", true), b = options("det_b", true);
  run::run_dataset(a);
  run::run_dataset(b);
  for (const char* f :
       {"trajectory_camera.txt", "trajectory_robot.txt", "keyframes.txt", "map.ot", "map.ply"}) {
    const std::string x = read_bytes(a.out_dir + "/" + f), y = read_bytes(b.out_dir + "/" + f);
    EXPECT_FALSE(x.empty()) << f;
    EXPECT_TRUE(x == y) << f << " differs between two deterministic runs";
  }
}

TEST(PipelineRun, InterruptedRunLeavesLoadableOutputs) {
  run::RunOptions o = options("interrupted", /*deterministic=*/false);
  o.stop_after_frames = 30;  // what the SIGINT flag does, at a reproducible point
  const run::RunResult r = run::run_dataset(o);
  EXPECT_TRUE(r.interrupted);
  EXPECT_EQ(r.frames_done, 30u);
  expect_loadable_outputs(o.out_dir, 30);
  EXPECT_TRUE(r.metrics["interrupted"].get<bool>());
}

// Every file under dir with its bytes.
std::map<std::string, std::string> folder_bytes(const std::string& dir) {
  std::map<std::string, std::string> out;
  for (const auto& e : fs::recursive_directory_iterator(dir))
    if (e.is_regular_file()) out[fs::relative(e.path(), dir).string()] = read_bytes(e.path().string());
  return out;
}

TEST(PipelineRun, ARunStoppedBeforeItsFirstFrameLeavesTheFolderAsItWas) {
  // Ctrl-C before the first frame over a complete earlier run: nothing is written over it.
  run::RunOptions o = options("stopped_at_once", /*deterministic=*/true);
  o.max_frames = 10;
  run::run_dataset(o);
  const auto before = folder_bytes(o.out_dir);
  ASSERT_TRUE(before.count("metrics.json") && before.count("trajectory_camera.txt"));
  o.stop_after_frames = 0;
  const run::RunResult r = run::run_dataset(o);
  EXPECT_TRUE(r.interrupted);
  EXPECT_FALSE(r.written);
  EXPECT_EQ(r.frames_done, 0u);
  EXPECT_TRUE(folder_bytes(o.out_dir) == before) << "the earlier run was changed";
  // Into a folder that did not exist: none is left behind.
  o.out_dir += "_new";
  fs::remove_all(o.out_dir);
  EXPECT_FALSE(run::run_dataset(o).written);
  EXPECT_FALSE(fs::exists(o.out_dir));
}

// f() throws s3m::Error whose message holds every part.
template <typename F>
void expect_error_containing(F f, const std::vector<std::string>& parts) {
  try {
    f();
    ADD_FAILURE() << "no error";
  } catch (const Error& e) {
    for (const std::string& part : parts)
      EXPECT_NE(std::string(e.what()).find(part), std::string::npos)
          << "'" << part << "' not in: " << e.what();
  }
}

// No staging folder of a command is left in a run's folder.
bool no_staging_left(const std::string& dir) {
  for (const auto& e : fs::directory_iterator(dir))
    if (e.path().filename().string().rfind(".s3m-staging", 0) == 0) return false;
  return true;
}

TEST(PipelineRun, StoppedAtSeveralPointsOverAnEarlierRunLeavesALoadableRunOfWhatWasProcessed) {
  run::RunOptions o = options("stopped_later", /*deterministic=*/true);
  o.max_frames = 40;
  run::run_dataset(o);
  for (const long stop : {12L, 25L}) {
    o.stop_after_frames = stop;
    const run::RunResult r = run::run_dataset(o);
    EXPECT_TRUE(r.interrupted && r.written);
    expect_loadable_outputs(o.out_dir, static_cast<std::size_t>(stop));
    EXPECT_EQ(io::read_tum_trajectory(o.out_dir + "/trajectory_camera.txt").size(), std::size_t(stop));
    EXPECT_TRUE(no_staging_left(o.out_dir));
  }
}

TEST(PipelineRun, AFailureWhileWritingLeavesTheEarlierRunAsItWas) {
  // What a full disk does halfway through the outputs: the earlier run stays whole, not half replaced.
  run::RunOptions o = options("failed_write", /*deterministic=*/true);
  o.max_frames = 10;
  run::run_dataset(o);
  const auto before = folder_bytes(o.out_dir);
  o.max_frames = 15;
  o.write_more = [](const std::string& dir) {
    std::ofstream(dir + "/session.mcap") << "half";
    throw Error("session.mcap: No space left on device");
  };
  o.more_names = {"session.mcap"};
  EXPECT_THROW(run::run_dataset(o), Error);
  EXPECT_TRUE(folder_bytes(o.out_dir) == before) << "the earlier run was changed by a run that failed";
  EXPECT_TRUE(no_staging_left(o.out_dir));
}

TEST(PipelineRun, AFolderHoldingARecordingOrAnotherRecordingsRunNeedsForce) {
  run::RunOptions o = options("foreign", /*deterministic=*/true);
  o.max_frames = 8;
  // 1. The recording itself.
  run::RunOptions into_recording = o;
  into_recording.out_dir = o.dataset_dir;
  expect_error_containing([&] { run::run_dataset(into_recording); },
                          {"holds the recording this run reads", "--force"});
  // 2. Another recording's run: refused, naming it and what would be replaced; nothing changes.
  fs::create_directories(o.out_dir);
  std::ofstream(o.out_dir + "/metrics.json") << R"({"inputs": {"dataset": "/data/another_flight"}})";
  std::ofstream(o.out_dir + "/map.ot") << "another flight's map";
  const auto before = folder_bytes(o.out_dir);
  expect_error_containing([&] { run::run_dataset(o); },
                          {"a run of /data/another_flight", "replacing metrics.json, map.ot", "--force"});
  EXPECT_TRUE(folder_bytes(o.out_dir) == before);
  // 3. With --force it is replaced; this recording's own run may then be run again without it.
  o.force = true;
  EXPECT_TRUE(run::run_dataset(o).written);
  EXPECT_NE(read_bytes(o.out_dir + "/map.ot"), "another flight's map");
  o.force = false;
  EXPECT_TRUE(run::run_dataset(o).written);
}

TEST(PipelineRun, ARunIntoAnEarlierRunsFolderLeavesNoneOfItsProductsBehind) {
  run::RunOptions full = options("stale", true);
  full.max_frames = 20;
  run::run_dataset(full);
  ASSERT_TRUE(fs::exists(full.out_dir + "/map.ot") && fs::exists(full.out_dir + "/map.ply"));
  fs::create_directories(full.out_dir + "/report");
  std::ofstream(full.out_dir + "/report/report.html") << "the earlier run's report";
  std::ofstream(full.out_dir + "/notes.txt") << "the user's own file";
  run::RunOptions slam_only = full;
  slam_only.slam_only = true;
  slam_only.max_frames = 10;
  run::run_dataset(slam_only);
  EXPECT_EQ(io::read_tum_trajectory(full.out_dir + "/trajectory_camera.txt").size(), 10u);
  for (const char* f : {"map.ot", "map.ply", "kept_clouds.bin", "report"})
    EXPECT_FALSE(fs::exists(full.out_dir + "/" + f)) << f << " of the earlier run is still there";
  EXPECT_EQ(read_bytes(full.out_dir + "/notes.txt"), "the user's own file");
}

TEST(PipelineRun, SlamOnlyWritesTrajectoriesAndNoMap) {
  run::RunOptions o = options("slam_only", true);
  o.slam_only = true;
  o.max_frames = 40;
  o.config.dataset.depth_registration = "auto";  // sim.yaml states it; checked here from the images
  const run::RunResult r = run::run_dataset(o);
  EXPECT_EQ(io::read_tum_trajectory(o.out_dir + "/trajectory_camera.txt").size(),
            r.metrics["tracked"].get<std::size_t>());
  EXPECT_FALSE(fs::exists(o.out_dir + "/map.ot"));
  EXPECT_TRUE(r.metrics["map"].empty());
  EXPECT_TRUE(r.metrics["segmentation"].empty());
  // The simulator's depth is registered; the run finds so from its images and says why.
  const std::string reg = r.metrics["inputs"]["depth_registration"].get<std::string>();
  EXPECT_EQ(reg.rfind("registered (depth edges", 0), 0u) << reg;
  // Its depth scale is plausible: a median in the simulated office's range, no warning.
  const double median_m = r.metrics["inputs"]["depth_median_m"].get<double>();
  EXPECT_GT(median_m, 1.0);
  EXPECT_LT(median_m, 5.0);
  EXPECT_FALSE(r.metrics["inputs"].contains("depth_scale_warning"));
}

TEST(PipelineRun, DepthFactorOffByFiveIsWarnedAndRunsOn) {
  // The sequence's 5000-per-metre depth read with a camera file that says 1000 (millimetres): the
  // run goes on (a large hall is legitimate) but metrics.json says what the median would be at 5000.
  run::RunOptions ref = options("depth_scale_ref", true), o = options("depth_scale", true);
  std::string yaml = read_bytes(sequence_dir() + "/camera.yaml");
  const auto at = yaml.find("depth_factor: 5000");
  ASSERT_NE(at, std::string::npos) << yaml;
  yaml.replace(at, 18, "depth_factor: 1000");
  fs::create_directories(o.out_dir);
  const std::string camera = (scratch_dir() / "camera_mm.yaml").string();
  std::ofstream(camera) << yaml;
  for (auto* opt : {&ref, &o}) {
    opt->slam_only = true;
    opt->max_frames = 3;
  }
  o.config.dataset.camera = camera;
  const double truth_m = run::run_dataset(ref).metrics["inputs"]["depth_median_m"].get<double>();
  const run::RunResult r = run::run_dataset(o);
  EXPECT_NEAR(r.metrics["inputs"]["depth_median_m"].get<double>(), 5 * truth_m, 1e-3);
  const std::string w = r.metrics["inputs"]["depth_scale_warning"].get<std::string>();
  EXPECT_NE(w.find("with depth factor 1000: farther than"), std::string::npos) << w;
  EXPECT_NE(w.find(fmt::format("with depth factor 5000 it would be {:.2f} m", truth_m)), std::string::npos)
      << w;
}

// Frame i's colour file, as the sequence's rgb.txt names it.
std::string rgb_file(const fs::path& dir, int i) {
  std::ifstream in(dir / "rgb.txt");
  std::string line;
  for (int n = 0; std::getline(in, line);)
    if (!line.empty() && line[0] != '#' && n++ == i) return line.substr(line.find(' ') + 1);
  ADD_FAILURE() << "no frame " << i << " in " << dir / "rgb.txt";
  return "";
}

// A copy of the sequence whose files are links, except the colour images of the frames given,
// replaced by the bytes given (a recording with a few bad files).
std::string sequence_with_bad_frames(const std::string& name, const std::map<int, std::string>& bad) {
  const fs::path dir = linked_copy(name, [](const fs::path&) { return false; });
  for (const auto& [i, bytes] : bad) {
    const fs::path rgb = dir / rgb_file(dir, i);
    EXPECT_TRUE(fs::is_symlink(rgb)) << rgb;
    fs::remove(rgb);  // the link, not the cached sequence's file
    std::ofstream(rgb, std::ios::binary) << bytes;
  }
  return dir.string();
}

TEST(PipelineRun, UnreadableFramesAreSkippedAndNamed) {
  // Two bad colour files (a PNG cut after its first 100 bytes, an empty file) in 45 frames: both
  // skipped with their file named, the other 43 tracked as usual.
  const std::string png_start = read_bytes(sequence_dir() + "/" + rgb_file(sequence_dir(), 0)).substr(0, 100);
  run::RunOptions o = options("skip", true);
  o.dataset_dir = sequence_with_bad_frames("skip_seq", {{20, png_start}, {35, ""}});
  o.slam_only = true;
  o.max_frames = 45;
  const run::RunResult r = run::run_dataset(o);
  EXPECT_FALSE(r.interrupted);
  EXPECT_EQ(r.frames_skipped, 2u);
  EXPECT_EQ(r.frames_done, 43u);
  const auto& skipped = r.metrics["skipped_frames"];
  ASSERT_EQ(skipped.size(), 2u) << skipped.dump();
  EXPECT_EQ(skipped[0]["index"].get<int>(), 20);
  EXPECT_EQ(skipped[1]["index"].get<int>(), 35);
  for (const auto& s : skipped) {
    const std::string e = s["error"].get<std::string>();
    EXPECT_NE(e.find("skip_seq/rgb/"), std::string::npos) << e;
    EXPECT_NE(e.find("8-bit colour image"), std::string::npos) << e;
  }
  EXPECT_NE(skipped[1]["error"].get<std::string>().find("file is empty"), std::string::npos);
  EXPECT_FALSE(r.metrics.contains("stopped_by"));
  EXPECT_EQ(io::read_tum_trajectory(o.out_dir + "/trajectory_camera.txt").size(),
            r.metrics["tracked"].get<std::size_t>());
  EXPECT_EQ(r.metrics["tracking"]["states"].value("LOST", 0), 0) << r.metrics["tracking"].dump();
}

TEST(PipelineRun, TooManyUnreadableFramesInARowStopAfterWritingOutputs) {
  run::RunOptions o = options("skip_stop", true);
  o.dataset_dir = sequence_with_bad_frames("skip_stop_seq", {{30, ""}, {31, ""}, {32, ""}});
  o.slam_only = true;
  o.config.dataset.max_unreadable_in_a_row = 2;
  try {
    run::run_dataset(o);
    FAIL() << "expected an error";
  } catch (const Error& e) {
    const std::string what = e.what();
    for (const std::string& part : std::vector<std::string>{
             "stopped at frame 32 of 60", "3 unreadable frames in a row",
             "dataset.max_unreadable_in_a_row is 2", "skip_stop_seq/" + rgb_file(sequence_dir(), 32),
             "the outputs of the 30 frames before it are in " + o.out_dir})
      EXPECT_NE(what.find(part), std::string::npos) << "missing '" << part << "' in: " << what;
  }
  // What came before is written and loadable, and says why it ends there.
  EXPECT_EQ(io::read_tum_trajectory(o.out_dir + "/trajectory_camera.txt").size(), 30u);
  const auto metrics = nlohmann::json::parse(read_bytes(o.out_dir + "/metrics.json"));
  EXPECT_TRUE(metrics["interrupted"].get<bool>());
  EXPECT_EQ(metrics["skipped_frames"].size(), 3u);
  EXPECT_NE(metrics["stopped_by"].get<std::string>().find("3 unreadable frames in a row"), std::string::npos);
}

TEST(PipelineRun, BadInputsAreClearErrors) {
  run::RunOptions o = options("bad", true);
  o.dataset_dir = (scratch_dir() / "no_such_dataset").string();
  try {
    run::run_dataset(o);
    FAIL() << "expected an error";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("no_such_dataset"), std::string::npos) << e.what();
  }
  o = options("bad", true);
  o.segmenter = "onnx:" + (scratch_dir() / "missing_model").string();
  try {
    run::run_dataset(o);
    FAIL() << "expected an error";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("missing_model"), std::string::npos) << e.what();
  }
  o = options("bad", true);
  o.segmenter = "magic";
  EXPECT_THROW(run::run_dataset(o), Error);
}

}  // namespace
}  // namespace s3m::it
