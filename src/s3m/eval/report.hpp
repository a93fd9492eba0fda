#pragma once
// Turning trajectory evaluations into what people read: a text table, metrics.json, and PNG plots
// drawn by tools/plot_trajectories.py (matplotlib, run with the system's python3 like evo does).
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "s3m/eval/trajectory_eval.hpp"

namespace s3m::eval {

// {"name", "matched", "ate": {"rmse_m", "mean_m", "median_m", "std_m", "min_m", "max_m"},
//  "rpe": {"trans_rmse_m", ..., "rot_rmse_deg", ..., "pairs"}, "alignment": {"scale", "T_gt_est"}}
nlohmann::json to_json(const TrajectoryEvaluation& ev);
// Top level repeats the first estimate's ate/rpe/matched (so '.ate.rmse_m' always works) and lists
// all under "estimates", plus the options used. Atomic write.
nlohmann::json metrics_json(const std::vector<TrajectoryEvaluation>& evals, const EvalOptions& options);
void write_metrics_json(const std::string& path, const std::vector<TrajectoryEvaluation>& evals,
                        const EvalOptions& options);

// Fixed-width table: one row per estimate, ATE and RPE columns in cm / deg.
std::string format_table(const std::vector<TrajectoryEvaluation>& evals, const EvalOptions& options);

// Everything the plot script needs: full ground truth, each estimate aligned into the ground-truth
// frame (all poses, not only matched ones), per-pose ATE and per-pair RPE.
nlohmann::json plot_data_json(const io::Trajectory& gt, const std::vector<io::Trajectory>& estimates,
                              const std::vector<TrajectoryEvaluation>& evals);

struct PlotResult {
  bool ok = false;
  std::vector<std::string> files;  // PNGs written
  std::string message;             // why not, when !ok (python or matplotlib missing, script error)
};
// Locates the script: $S3M_TOOLS_DIR/plot_trajectories.py, else the shipped tools/ folder
// (s3m/core/shipped_files.hpp). Interpreter:
// $S3M_PYTHON, else /usr/bin/python3, else python3 on PATH. Never throws for a missing plotting
// environment: metrics stay valid without pictures, so the caller reports PlotResult::message.
PlotResult run_plot_script(const std::string& plot_data_path, const std::string& out_dir);
std::string find_tools_dir();  // empty when not found

// Everything `s3m eval --out DIR` writes: metrics.json, <name>_aligned.txt per estimate (TUM format,
// in the ground-truth frame), plot_data.json and, when plots is true, the PNGs. DIR is created.
// Throws s3m::Error when a file cannot be written; a missing plotting environment is only reported
// in the returned PlotResult.
PlotResult write_evaluation_report(const std::string& out_dir, const io::Trajectory& gt,
                                   const std::vector<io::Trajectory>& estimates,
                                   const std::vector<TrajectoryEvaluation>& evals, const EvalOptions& options,
                                   bool plots = true);

}  // namespace s3m::eval
