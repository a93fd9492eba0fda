// `s3m run`: the full pipeline on a TUM-layout dataset (real or simulated), a ROS 2 recording or, in
// ROS builds, a ROS1 bag.
#include <filesystem>
#include <iostream>
#include <optional>

#include <spdlog/spdlog.h>

#include "commands.hpp"
#include "interrupt.hpp"
#include "ros_support.hpp"
#include "s3m/core/error.hpp"
#include "s3m/core/frame_state.hpp"
#include "s3m/pipeline/factories.hpp"
#include "s3m/rosbag2/session_writer.hpp"
#include "s3m/run/progress.hpp"
#include "s3m/run/run.hpp"

namespace s3m::apps {

namespace {

struct RunArgs {
  std::string dataset, config, out, segmenter, model_dir, poses = "slam", vocab, map;
  bool localize_only = false, slam_only = false, deterministic = false, no_report = false,
       no_loop_closing = false, force = false, no_session_mcap = false, keep_dynamic = false, dynamic = false;
  long max_frames = -1;
  RosbagArgs bag;
};

void print_summary(const run::RunResult& r, const std::string& out) {
  if (!r.written) return;  // nothing was processed, nothing to sum up
  const auto& m = r.metrics;
  std::cout << "frames: " << r.frames_done << "/" << r.frames_total
            << (r.interrupted ? " (interrupted)" : "");
  if (r.frames_skipped > 0)
    std::cout << " (" << r.frames_skipped << " unreadable, skipped: metrics.json skipped_frames)";
  std::cout << ", keyframes: " << m.value("keyframes", 0) << ", " << m.value("fps", 0.0) << " frames/s\n";
  if (m.contains("tracking")) {
    const auto& t = m["tracking"];
    const auto frames_in = [&t](FrameState s) { return t["states"].value(to_string(s), 0); };
    std::cout << "tracking: " << frames_in(FrameState::kLost) << " frames LOST, "
              << t["relocalised_frames"].size() << " RELOCALISED, ";
    if (const int n = frames_in(FrameState::kOdometry); n > 0)
      std::cout << n << " ODOMETRY (posed by depth odometry), ";
    std::cout << m.value("corrections", 0) << " loop corrections applied to the map\n";
    if (t.contains("submaps") && t["submaps"].value("started", 0) > 0) {
      const auto& sub = t["submaps"];
      std::cout << "sub-maps: " << sub["started"] << " started after relocalisation failed ("
                << frames_in(FrameState::kSubmap) << " frames tracked in them), " << sub["merges"]
                << " merged, " << sub["keyframes_outside_world"] << " keyframes never met the map\n";
      if (sub.value("world_moved", false))
        std::cout
            << "world: the sub-map with the most tracked frames (loop_closing.merge.world); left out of the "
            << "trajectory and the map: " << sub.value("frames_outside_world", 0)
            << " tracked frame(s) of the others\n";
    }
  }
  if (m.contains("trajectory") && m["trajectory"].contains("ate_rmse_m"))
    std::cout << "ATE RMSE: " << m["trajectory"]["ate_rmse_m"].get<double>() << " m\n";
  else if (m.contains("trajectory") && m["trajectory"].contains("error"))  // ground truth there, unusable
    std::cout << "ATE: not computed: " << m["trajectory"]["error"].get<std::string>() << "\n";
  if (m.contains("segmentation") && m["segmentation"].contains("miou"))
    std::cout << "segmentation mIoU (single frame): " << m["segmentation"]["miou"].get<double>() << "\n";
  if (m.contains("map") && m["map"].contains("miou"))
    std::cout << "map mIoU (fused): " << m["map"]["miou"].get<double>() << "\n";
  // Said before the first frame too, but a long run's log has scrolled it away by now.
  if (m.contains("inputs") && m["inputs"].contains("depth_scale_warning"))
    std::cout << "warning: " << m["inputs"]["depth_scale_warning"].get<std::string>() << "\n";
  std::cout << "outputs: " << out << "\n";
  if (!r.report_html.empty()) std::cout << "report: " << r.report_html << "\n";
}

}  // namespace

void register_run(CLI::App& app) {
  auto args = std::make_shared<RunArgs>();
  auto* cmd = app.add_subcommand("run",
                                 "Run SLAM + segmentation + semantic mapping on an RGB-D dataset folder (TUM "
                                 "layout, ETH3D, 7-Scenes, ScanNet, Replica)");
  cmd->add_option(
      "dataset", args->dataset,
      "TUM-layout directory (rgb.txt, depth.txt, ...; ETH3D too), a 7-Scenes folder as downloaded "
      "(frame-NNNNNN.color.png, ...), a ScanNet export (color/, depth/, ...), a Replica scene "
      "(results/, traj.txt) or a ROS 2 recording (.mcap, .db3, or a rosbag2 folder with metadata.yaml); "
      "omit with --rosbag");
  cmd->add_option("--config", args->config,
                  "pipeline preset, e.g. config/tum_fr1.yaml (default: built-in defaults)");
  cmd->add_option("--out", args->out, "output directory")->required();
  cmd->add_option("--segmenter", args->segmenter,
                  "onnx:MODEL_DIR_OR_CARD | oracle | none (default: the config's segmenter section)");
  cmd->add_option("--model-dir", args->model_dir,
                  "with onnx: folder holding the model files (card elsewhere)");
  cmd->add_option("--poses", args->poses,
                  "slam (default) | gt: ground-truth poses, to evaluate mapping alone")
      ->check(CLI::IsMember({"slam", "gt"}));
  cmd->add_flag("--slam-only", args->slam_only, "trajectories only (no segmentation, no map)");
  cmd->add_flag("--deterministic", args->deterministic, "single thread, identical output run to run");
  cmd->add_flag("--dynamic", args->dynamic,
                "the scene has things that move (dynamic.classes, default person): tracking uses no keypoint "
                "on them and the map does not make them obstacles (dynamic.enabled)");
  cmd->add_flag("--keep-dynamic", args->keep_dynamic,
                "with --dynamic: map the classes that move like any other (dynamic.keep_in_map)");
  cmd->add_flag("--no-loop-closing", args->no_loop_closing,
                "SLAM without loop closing and relocalisation (preset: loop_closing.enabled/relocalisation)");
  cmd->add_option("--vocab", args->vocab,
                  "bag-of-words vocabulary (default: the preset's, else vocab/orb_k10_l5.bin)");
  cmd->add_option(
      "--map", args->map,
      "continue in the session a previous run wrote into this folder (slam_map.bin, kept_clouds.bin): "
      "relocalise in it, report poses in its world, extend it");
  cmd->add_flag(
      "--localize-only", args->localize_only,
      "with --map: localise only, the SLAM map stays as loaded (the semantic map still fuses this run)");
  cmd->add_option("--max-frames", args->max_frames, "process at most N frames")->check(count_option());
  cmd->add_flag("--no-report", args->no_report, "skip the plots and report.html");
  cmd->add_flag("--no-session-mcap", args->no_session_mcap,
                "skip OUT/session.mcap (trajectories as /tf and nav_msgs/Path, the map as PointCloud2 and "
                "MarkerArray, for Foxglove and ros2 bag play)");
  cmd->add_flag("--force", args->force,
                "run even when the map's cost estimate (voxel updates per frame, checked before the first "
                "frame) is over its limit, and write into an --out folder that holds a recording or a run of "
                "another recording (its outputs are replaced)");
  add_rosbag_options(*cmd, args->bag);
  cmd->callback([args] {
    run::RunOptions o;
    if (args->bag.bag.empty() == args->dataset.empty())
      throw Error("run: give either a dataset directory or --rosbag FILE.bag (exactly one)");
    o.dataset_dir = args->dataset;
    if (!args->bag.bag.empty()) o.open_source = rosbag_source(args->bag);
    o.out_dir = args->out;
    o.config =
        args->config.empty() ? pipeline::PipelineConfig{} : pipeline::load_pipeline_config(args->config);
    // Options that set config keys count as written: automatic decisions leave them as set.
    if (args->deterministic) {
      o.config.threads.deterministic = true;
      pipeline::mark_written(o.config, "threads.deterministic");
    }
    if (args->dynamic) {
      o.config.dynamic.enabled = true;
      pipeline::mark_written(o.config, "dynamic.enabled");
    }
    if (args->keep_dynamic) {
      o.config.dynamic.keep_in_map = true;
      pipeline::mark_written(o.config, "dynamic.keep_in_map");
    }
    // Without a preset a simulator sequence's camera mount comes from its sim.yaml; robot poses
    // would otherwise be camera poses (identity T_c_r) and the robot's ATE/RPE meaningless.
    if (args->config.empty())
      if (const auto T_c_r = pipeline::simulator_T_c_r(args->dataset)) {
        o.config.slam.T_c_r = *T_c_r;
        spdlog::info("run: no --config: T_c_r (robot -> camera) from {}/sim.yaml", args->dataset);
      }
    if (args->no_loop_closing) {
      o.config.slam.loop_closing.enabled = o.config.slam.loop_closing.relocalisation = false;
      pipeline::mark_written(o.config, "loop_closing.enabled");
      pipeline::mark_written(o.config, "loop_closing.relocalisation");
    }
    if (!args->vocab.empty()) {
      o.config.slam.loop_closing.vocabulary = args->vocab;
      pipeline::mark_written(o.config, "loop_closing.vocabulary");
    }
    std::optional<PinholeCamera> camera;  // for session.mcap, with the keyframes' segmentations
    auto keyframes = std::make_shared<std::vector<rosbag2::KeyframeLabels>>();
    if (!args->no_session_mcap)
      o.on_frame = [keyframes](const pipeline::FrameOutcome& f, const RgbdFrame&,
                               const semantics::LabelMap& l) {
        if (f.keyframe && !l.empty()) keyframes->push_back({f.t_s, rosbag2::keyframe_png(l.argmax)});
      };
    if (is_ros2_recording(args->dataset))
      o.open_source =
          ros2_source(args->dataset, args->bag, o.config, !args->config.empty(), &camera.emplace());
    o.segmenter = args->segmenter;
    o.model_dir = args->model_dir;
    o.poses = args->poses;
    o.slam_only = args->slam_only;
    o.max_frames = args->max_frames;
    o.map_dir = args->map;
    o.localize_only = args->localize_only;
    o.report = !args->no_report;
    o.force = args->force;
    o.progress = run::stderr_is_tty();
    o.stop = &install_interrupt_handler();
    o.more_names = {"session.mcap"};  // an earlier run's would not match this run's outputs
    if (!args->no_session_mcap)
      o.write_more = [&camera, &o, args, keyframes](const std::string& dir) {
        if (!camera && args->bag.bag.empty())  // a dataset folder: its camera, read again (cheap)
          camera = pipeline::open_tum_source(args->dataset, o.config.dataset)->camera();
        rosbag2::write_session_mcap(dir, camera ? &*camera : nullptr, *keyframes);
      };
    const run::RunResult r = run::run_dataset(o);
    print_summary(r, args->out);
    if (r.interrupted)
      throw Interrupted("run: stopped after " + std::to_string(r.frames_done) + " of " +
                        std::to_string(r.frames_total) + " frames; " + args->out +
                        (r.written ? " holds those frames" : " is left as it was"));
  });
}

}  // namespace s3m::apps
