#include "s3m/eval/report.hpp"

#include <spawn.h>
#include <sys/wait.h>

#include <cctype>
#include <cstdlib>
#include <filesystem>
#include <sstream>

#include <fmt/format.h>

#include "s3m/core/error.hpp"
#include "s3m/core/shipped_files.hpp"
#include "s3m/io/atomic_file.hpp"

extern char** environ;

namespace s3m::eval {
namespace fs = std::filesystem;
using nlohmann::json;

namespace {

json stats_json(const ErrorStats& s, const std::string& prefix, const std::string& unit) {
  return {{prefix + "rmse_" + unit, s.rmse}, {prefix + "mean_" + unit, s.mean}, {prefix + "median_" + unit, s.median},
          {prefix + "std_" + unit, s.std},   {prefix + "min_" + unit, s.min},   {prefix + "max_" + unit, s.max}};
}

json position_arrays(const std::vector<SE3>& poses) {
  json x = json::array(), y = json::array(), z = json::array();
  for (const auto& T : poses) {
    x.push_back(T.translation().x());
    y.push_back(T.translation().y());
    z.push_back(T.translation().z());
  }
  return {{"x", x}, {"y", y}, {"z", z}};
}

}  // namespace

json to_json(const TrajectoryEvaluation& ev) {
  json ate = stats_json(ev.ate.stats_m, "", "m");
  json rpe = stats_json(ev.rpe.trans_m, "trans_", "m");
  rpe.update(stats_json(ev.rpe.rot_deg, "rot_", "deg"));
  rpe["pairs"] = ev.rpe.trans_m.count;
  const Quat q(ev.ate.alignment.T_gt_est.linear());
  const Vec3 t = ev.ate.alignment.T_gt_est.translation();
  return {{"name", ev.name},
          {"matched", ev.matched},
          {"est_poses", ev.est_poses},
          {"gt_poses", ev.gt_poses},
          {"ate", ate},
          {"rpe", rpe},
          {"alignment", {{"scale", ev.ate.alignment.scale}, {"t_xyz_m", {t.x(), t.y(), t.z()}},
                         {"q_xyzw", {q.x(), q.y(), q.z(), q.w()}}}}};
}

json metrics_json(const std::vector<TrajectoryEvaluation>& evals, const EvalOptions& options) {
  json out;
  if (!evals.empty()) {
    const json first = to_json(evals.front());
    for (const char* key : {"name", "matched", "ate", "rpe"}) out[key] = first[key];
  }
  out["estimates"] = json::array();
  for (const auto& ev : evals) out["estimates"].push_back(to_json(ev));
  out["options"] = {{"align", to_string(options.align)},
                    {"max_dt_s", options.max_dt_s},
                    {"offset_s", options.offset_s},
                    {"rpe_delta", options.rpe.delta},
                    {"rpe_delta_unit", options.rpe.unit == DeltaUnit::kSeconds ? "s" : "f"}};
  return out;
}

void write_metrics_json(const std::string& path, const std::vector<TrajectoryEvaluation>& evals,
                        const EvalOptions& options) {
  io::write_text_atomic(path, metrics_json(evals, options).dump(2) + "\n");
}

std::string format_table(const std::vector<TrajectoryEvaluation>& evals, const EvalOptions& options) {
  std::ostringstream os;
  const std::string delta = fmt::format("{:g} {}", options.rpe.delta, options.rpe.unit == DeltaUnit::kSeconds ? "s" : "frames");
  os << fmt::format("alignment: {}   association: max {:g} s   RPE delta: {}\n", to_string(options.align),
                    options.max_dt_s, delta);
  os << fmt::format("{:<24} {:>9} {:>9} {:>9} {:>9} {:>9} {:>9} {:>10} {:>10} {:>7}\n", "estimate", "matched",
                    "ATE rmse", "mean", "median", "std", "max", "RPE t rmse", "RPE r rmse", "scale");
  os << fmt::format("{:<24} {:>9} {:>9} {:>9} {:>9} {:>9} {:>9} {:>10} {:>10} {:>7}\n", "", "", "[cm]", "[cm]",
                    "[cm]", "[cm]", "[cm]", "[cm]", "[deg]", "");
  for (const auto& ev : evals) {
    const auto& a = ev.ate.stats_m;
    std::string name = ev.name.size() > 24 ? "..." + ev.name.substr(ev.name.size() - 21) : ev.name;
    os << fmt::format("{:<24} {:>9} {:>9.3f} {:>9.3f} {:>9.3f} {:>9.3f} {:>9.3f} {:>10.3f} {:>10.3f} {:>7.4f}\n", name,
                      fmt::format("{}/{}", ev.matched, ev.est_poses), 100 * a.rmse, 100 * a.mean, 100 * a.median,
                      100 * a.std, 100 * a.max, 100 * ev.rpe.trans_m.rmse, ev.rpe.rot_deg.rmse, ev.ate.alignment.scale);
  }
  return os.str();
}

json plot_data_json(const io::Trajectory& gt, const std::vector<io::Trajectory>& estimates,
                    const std::vector<TrajectoryEvaluation>& evals) {
  std::vector<SE3> gt_poses;
  json gt_t = json::array();
  for (const auto& p : gt) gt_poses.push_back(p.T_w_x), gt_t.push_back(p.t_s);
  json out = {{"gt", position_arrays(gt_poses)}, {"estimates", json::array()}};
  out["gt"]["t"] = gt_t;
  for (std::size_t k = 0; k < evals.size() && k < estimates.size(); ++k) {
    const auto& ev = evals[k];
    std::vector<SE3> aligned, matched_aligned;
    json t_all = json::array();
    for (const auto& p : estimates[k]) aligned.push_back(ev.ate.alignment.apply(p.T_w_x)), t_all.push_back(p.t_s);
    for (const auto& T : ev.poses.T_w_est) matched_aligned.push_back(ev.ate.alignment.apply(T));
    json e = {{"name", ev.name}, {"aligned", position_arrays(aligned)}, {"ate", position_arrays(matched_aligned)}};
    e["aligned"]["t"] = t_all;
    e["ate"]["t"] = ev.poses.t_s;
    e["ate"]["error_m"] = ev.ate.errors_m;
    e["ate"]["rmse_m"] = ev.ate.stats_m.rmse;
    e["rpe"] = {{"t", ev.rpe.t_s}, {"trans_m", ev.rpe.trans_errors_m}, {"rot_deg", ev.rpe.rot_errors_deg}};
    out["estimates"].push_back(e);
  }
  return out;
}

std::string find_tools_dir() {
  if (const char* env = std::getenv("S3M_TOOLS_DIR"); env && *env) return env;
  const fs::path script = shipped_file("tools/plot_trajectories.py");
  return fs::exists(script) ? script.parent_path().string() : std::string();
}

namespace {
std::string find_python() {
  if (const char* env = std::getenv("S3M_PYTHON"); env && *env) return env;
  // Debian's interpreter has numpy/matplotlib from apt; a pyenv 'python3' first on PATH may not.
  if (fs::exists("/usr/bin/python3")) return "/usr/bin/python3";
  return "python3";
}

// Runs argv without a shell (paths with spaces are safe); returns the exit code, -1 if it cannot start.
int run_process(const std::vector<std::string>& args) {
  std::vector<char*> argv;
  for (const auto& a : args) argv.push_back(const_cast<char*>(a.c_str()));
  argv.push_back(nullptr);
  pid_t pid = 0;
  if (posix_spawnp(&pid, argv[0], nullptr, nullptr, argv.data(), environ) != 0) return -1;
  int status = 0;
  if (waitpid(pid, &status, 0) < 0) return -1;
  return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
}
}  // namespace

PlotResult run_plot_script(const std::string& plot_data_path, const std::string& out_dir) {
  PlotResult r;
  const std::string tools = find_tools_dir();
  const fs::path script = fs::path(tools) / "plot_trajectories.py";
  if (tools.empty() || !fs::exists(script)) {
    r.message = "plot script tools/plot_trajectories.py not found (set S3M_TOOLS_DIR to the repository's tools/ folder)";
    return r;
  }
  const std::string python = find_python();
  const int rc = run_process({python, script.string(), plot_data_path, out_dir});
  if (rc == -1) {
    r.message = "cannot run '" + python + "' (install python3 and python3-matplotlib, or set S3M_PYTHON)";
  } else if (rc == 3) {
    r.message = "python3 has no matplotlib (apt-get install python3-matplotlib, or set S3M_PYTHON)";
  } else if (rc != 0) {
    r.message = fmt::format("plot script failed with exit code {} (see its output above)", rc);
  } else {
    r.ok = true;
    for (const char* f : {"trajectory_xy.png", "trajectory_xz.png", "rpe.png", "ate.png"})
      if (fs::exists(fs::path(out_dir) / f)) r.files.push_back((fs::path(out_dir) / f).string());
  }
  return r;
}

PlotResult write_evaluation_report(const std::string& out_dir, const io::Trajectory& gt,
                                   const std::vector<io::Trajectory>& estimates,
                                   const std::vector<TrajectoryEvaluation>& evals, const EvalOptions& options,
                                   bool plots) {
  require(estimates.size() == evals.size(), "write_evaluation_report: one evaluation per estimate expected");
  std::error_code ec;
  fs::create_directories(out_dir, ec);
  if (ec) throw Error("cannot create output directory '" + out_dir + "': " + ec.message());
  const fs::path out(out_dir);
  // 1. Numbers first: they must exist even if plotting fails.
  write_metrics_json((out / "metrics.json").string(), evals, options);
  // 2. Aligned estimates, so other tools can overlay them without redoing the alignment.
  for (std::size_t i = 0; i < evals.size(); ++i) {
    io::Trajectory aligned = estimates[i];
    for (auto& p : aligned) p.T_w_x = evals[i].ate.alignment.apply(p.T_w_x);
    std::string file = evals[i].name;  // a display name may hold '/' or spaces: keep file names tame
    for (char& c : file)
      if (!std::isalnum(static_cast<unsigned char>(c)) && c != '-' && c != '_' && c != '.') c = '_';
    io::write_tum_trajectory((out / (file + "_aligned.txt")).string(), aligned);
  }
  // 3. Plot data and pictures.
  const std::string plot_data = (out / "plot_data.json").string();
  io::write_text_atomic(plot_data, plot_data_json(gt, estimates, evals).dump() + "\n");
  if (!plots) return {true, {}, "plots disabled"};
  return run_plot_script(plot_data, out_dir);
}

}  // namespace s3m::eval
