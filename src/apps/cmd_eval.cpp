// s3m eval: ATE/RPE of one or more estimated trajectories against ground truth, with plots.
#include <filesystem>
#include <iostream>

#include "commands.hpp"
#include "s3m/core/error.hpp"
#include "s3m/eval/report.hpp"
#include "s3m/io/frame_folders.hpp"
#include "s3m/io/trajectory.hpp"

namespace s3m::apps {
namespace {
namespace fs = std::filesystem;

struct EvalArgs {
  std::string gt;
  std::vector<std::string> est, est2, names;
  std::string align = "se3", delta_unit = "s", format = "auto", out;
  double delta = 1.0, max_dt_s = 0.02, offset_s = 0.0, kitti_dt_s = 0.1;
  bool no_plots = false;
};

io::Trajectory read_any(const std::string& path, const EvalArgs& a) {
  if (a.format == "tum") return io::read_tum_trajectory(path);
  if (a.format == "kitti") return io::read_kitti_trajectory(path, a.kitti_dt_s);
  return io::read_trajectory_auto(path, a.kitti_dt_s);
}

// A folder whose ground truth is one pose file per frame (7-Scenes, ScanNet), not groundtruth.txt.
bool pose_file_folder(const std::string& path) {
  return fs::is_directory(path) && !fs::exists(fs::path(path) / "groundtruth.txt") &&
         io::folder_layout(path) != io::FolderLayout::kNone;
}

// --gt: a trajectory file, or a dataset folder: its groundtruth.txt, or its pose files.
CLI::Validator ground_truth_source() {
  const auto tum_folder = file_or_folder("groundtruth.txt", "a dataset without ground truth?");
  return CLI::Validator(
      [tum_folder](std::string& path) -> std::string {
        if (pose_file_folder(path)) return "";
        const std::string problem = tum_folder(path);
        return problem.empty() ? CLI::ExistingFile(path) : problem;
      },
      "groundtruth.txt|FOLDER");
}

io::Trajectory read_ground_truth(const EvalArgs& a) {
  if (!fs::is_directory(a.gt)) return read_any(a.gt, a);
  io::Trajectory gt;
  const io::FolderLayout layout = io::folder_layout(a.gt);
  for (const auto& f : io::read_folder_frames(a.gt, layout))
    if (f.T_w_c) gt.push_back({f.t_s, *f.T_w_c});
  if (gt.empty()) throw ParseError(a.gt, 0, "no finite pose in its pose files", "a " + io::layout_name(layout) + " with ground truth");
  return gt;
}

// A file's display name: its stem, or for s3m run's trajectory_camera.txt (every run's) its folder's.
std::string display_name(const std::string& file) {
  const fs::path p = fs::absolute(file).lexically_normal();
  if (p.filename() == "trajectory_camera.txt" && !p.parent_path().filename().empty())
    return p.parent_path().filename().string();
  return p.stem().string();
}

std::vector<std::string> unique_names(const std::vector<std::string>& files, const std::vector<std::string>& given) {
  std::vector<std::string> names;
  for (std::size_t i = 0; i < files.size(); ++i) {
    std::string n = i < given.size() ? given[i] : display_name(files[i]);
    for (const auto& prev : names)
      if (prev == n) n += "_" + std::to_string(i + 1);
    names.push_back(n);
  }
  return names;
}

void run_eval(const EvalArgs& a) {
  eval::EvalOptions opt;
  opt.align = eval::parse_align_mode(a.align);
  opt.rpe.delta = a.delta;
  opt.rpe.unit = eval::parse_delta_unit(a.delta_unit);
  opt.max_dt_s = a.max_dt_s;
  opt.offset_s = a.offset_s;
  opt.validate();
  // 1. Read everything first so a bad file fails before any output is written.
  std::vector<std::string> files = a.est;
  files.insert(files.end(), a.est2.begin(), a.est2.end());
  const auto gt = read_ground_truth(a);
  std::vector<io::Trajectory> estimates;
  for (const auto& f : files) estimates.push_back(read_any(f, a));
  // 2. Evaluate each estimate.
  const auto names = unique_names(files, a.names);
  std::vector<eval::TrajectoryEvaluation> evals;
  for (std::size_t i = 0; i < files.size(); ++i) evals.push_back(eval::evaluate_trajectory(gt, estimates[i], opt, names[i]));
  std::cout << eval::format_table(evals, opt);
  if (a.out.empty()) return;
  // 3. Files: metrics, aligned trajectories, plot data and plots.
  const auto plots = eval::write_evaluation_report(a.out, gt, estimates, evals, opt, !a.no_plots);
  std::cout << "wrote " << (fs::path(a.out) / "metrics.json").string() << "\n";
  if (!plots.ok) {
    std::cerr << "s3m eval: warning: no plots: " << plots.message << " (metrics.json is complete)\n";
    return;
  }
  for (const auto& f : plots.files) std::cout << "wrote " << f << "\n";
}

}  // namespace

void register_eval(CLI::App& app) {
  auto args = std::make_shared<EvalArgs>();
  auto* cmd = app.add_subcommand("eval", "Evaluate trajectories against ground truth: ATE, RPE, plots (TUM definitions)");
  cmd->add_option("--gt", args->gt,
                  "Ground-truth trajectory (TUM 't tx ty tz qx qy qz qw' or KITTI 3x4), or a dataset folder (its "
                  "groundtruth.txt; a 7-Scenes, ScanNet or Replica folder's poses at t = N / 30 s)")
      ->required()
      ->transform(ground_truth_source());
  const auto run_folder = file_or_folder("trajectory_camera.txt", "not a folder s3m run wrote?");
  cmd->add_option("--est", args->est, "Estimated trajectory file(s), or s3m run output folder(s) (trajectory_camera.txt)")
      ->required()
      ->transform(run_folder)
      ->check(CLI::ExistingFile);
  cmd->add_option("--est2", args->est2, "Further estimates to compare (overlaid in the plots)")
      ->transform(run_folder)
      ->check(CLI::ExistingFile);
  cmd->add_option("--name", args->names, "Display names for the estimates, in order (default: file stems; a run's folder name)");
  cmd->add_option("--align", args->align, "Alignment before ATE: se3 (Horn), sim3 (with scale, monocular) or none")
      ->check(CLI::IsMember({"se3", "sim3", "none"}))->capture_default_str();
  cmd->add_option("--delta", args->delta, "RPE pair distance")->capture_default_str();
  cmd->add_option("--delta-unit", args->delta_unit, "RPE delta unit: s (seconds) or f (frames)")
      ->check(CLI::IsMember({"s", "f"}))->capture_default_str();
  cmd->add_option("--max-dt", args->max_dt_s, "Max timestamp difference for association [s]")->capture_default_str();
  cmd->add_option("--offset", args->offset_s, "Time offset added to the estimate's timestamps [s]")->capture_default_str();
  cmd->add_option("--format", args->format, "Trajectory format: auto, tum or kitti")
      ->check(CLI::IsMember({"auto", "tum", "kitti"}))->capture_default_str();
  cmd->add_option("--kitti-dt", args->kitti_dt_s, "Frame period for KITTI files (no timestamps) [s]")->capture_default_str();
  cmd->add_option("--out", args->out, "Output directory for metrics.json, aligned trajectories and PNG plots");
  cmd->add_flag("--no-plots", args->no_plots, "Write metrics only");
  cmd->callback([args] { run_eval(*args); });
}

}  // namespace s3m::apps
