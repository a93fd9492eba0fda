// `s3m run`: the full pipeline on a TUM-layout dataset (real or simulated) or, in ROS builds, a rosbag.
#include <iostream>

#include <spdlog/spdlog.h>

#include "commands.hpp"
#include "interrupt.hpp"
#include "ros_support.hpp"
#include "s3m/core/error.hpp"
#include "s3m/pipeline/progress.hpp"
#include "s3m/pipeline/run.hpp"

namespace s3m::apps {

namespace {

struct RunArgs {
  std::string dataset, config, out, segmenter, model_dir, poses = "slam";
  bool slam_only = false, deterministic = false, no_report = false;
  long max_frames = -1;
  RosbagArgs bag;
};

void print_summary(const pipeline::RunResult& r, const std::string& out) {
  const auto& m = r.metrics;
  std::cout << "frames: " << r.frames_done << "/" << r.frames_total << (r.interrupted ? " (interrupted)" : "")
            << ", keyframes: " << m.value("keyframes", 0) << ", " << m.value("fps", 0.0) << " frames/s\n";
  if (m.contains("trajectory") && m["trajectory"].contains("ate_rmse_m"))
    std::cout << "ATE RMSE: " << m["trajectory"]["ate_rmse_m"].get<double>() << " m\n";
  if (m.contains("segmentation") && m["segmentation"].contains("miou"))
    std::cout << "segmentation mIoU (single frame): " << m["segmentation"]["miou"].get<double>() << "\n";
  if (m.contains("map") && m["map"].contains("miou"))
    std::cout << "map mIoU (fused): " << m["map"]["miou"].get<double>() << "\n";
  std::cout << "outputs: " << out << "\n";
  if (!r.report_html.empty()) std::cout << "report: " << r.report_html << "\n";
}

}  // namespace

void register_run(CLI::App& app) {
  auto args = std::make_shared<RunArgs>();
  auto* cmd = app.add_subcommand("run", "Run SLAM + segmentation + semantic mapping on a TUM-layout dataset");
  cmd->add_option("dataset", args->dataset, "TUM-layout directory (rgb.txt, depth.txt, ...); omit with --rosbag");
  cmd->add_option("--config", args->config, "pipeline preset, e.g. config/tum_fr1.yaml (default: built-in defaults)");
  cmd->add_option("--out", args->out, "output directory")->required();
  cmd->add_option("--segmenter", args->segmenter,
                  "onnx:MODEL_DIR_OR_CARD | oracle | none (default: the config's segmenter section)");
  cmd->add_option("--model-dir", args->model_dir, "with onnx: folder holding the model files (card elsewhere)");
  cmd->add_option("--poses", args->poses, "slam (default) | gt: ground-truth poses, to evaluate mapping alone")
      ->check(CLI::IsMember({"slam", "gt"}));
  cmd->add_flag("--slam-only", args->slam_only, "trajectories only (no segmentation, no map)");
  cmd->add_flag("--deterministic", args->deterministic, "single thread, identical output run to run");
  cmd->add_option("--max-frames", args->max_frames, "process at most N frames");
  cmd->add_flag("--no-report", args->no_report, "skip the plots and report.html");
  add_rosbag_options(*cmd, args->bag);
  cmd->callback([args] {
    pipeline::RunOptions o;
    if (args->bag.bag.empty() == args->dataset.empty())
      throw Error("run: give either a dataset directory or --rosbag FILE.bag (exactly one)");
    o.dataset_dir = args->dataset;
    if (!args->bag.bag.empty()) o.open_source = rosbag_source(args->bag);
    o.out_dir = args->out;
    o.config = args->config.empty() ? pipeline::PipelineConfig{} : pipeline::load_pipeline_config(args->config);
    if (args->deterministic) o.config.threads.deterministic = true;
    o.segmenter = args->segmenter;
    o.model_dir = args->model_dir;
    o.poses = args->poses;
    o.slam_only = args->slam_only;
    o.max_frames = args->max_frames;
    o.report = !args->no_report;
    o.progress = pipeline::stderr_is_tty();
    o.stop = &install_interrupt_handler();
    print_summary(pipeline::run_dataset(o), args->out);
  });
}

}  // namespace s3m::apps
