#include "s3m/run/report.hpp"

#include <cstdlib>
#include <filesystem>

#include "s3m/eval/report.hpp"

namespace s3m::run {
namespace fs = std::filesystem;

namespace {

std::string shell_quote(const std::string& s) {
  std::string q = "'";
  for (char ch : s) q += ch == '\'' ? std::string("'\\''") : std::string(1, ch);
  return q + "'";
}

}  // namespace

ReportResult make_report(const std::string& out_dir) {
  ReportResult r;
  // Trajectory X-Y / X-Z, RPE over time, ATE along the path: the evaluator's plots, same as `s3m eval`.
  const std::string plot_data = out_dir + "/report/plot_data.json";
  if (fs::exists(plot_data)) {
    const eval::PlotResult traj = eval::run_plot_script(plot_data, out_dir + "/report");
    if (!traj.ok) r.error = "trajectory plots: " + traj.message + "; ";
  }
  // Same lookup as the evaluator's script ($S3M_TOOLS_DIR, else the source tree's tools/).
  const std::string script = eval::find_tools_dir() + "/plot_report.py";
  if (!fs::exists(script)) {
    r.error += "plot script " + script + " not found (set S3M_TOOLS_DIR to the repository's tools/)";
    return r;
  }
  // Debian's interpreter has numpy/matplotlib; a pyenv/venv python3 on PATH usually does not.
  const std::string python = fs::exists("/usr/bin/python3") ? "/usr/bin/python3" : "python3";
  const std::string log = out_dir + "/report/plot_report.log";
  std::error_code ec;
  fs::create_directories(out_dir + "/report", ec);
  if (ec) {
    r.error += "cannot create " + out_dir + "/report: " + ec.message();
    return r;
  }
  const std::string cmd =
      python + " " + shell_quote(script) + " " + shell_quote(out_dir) + " > " + shell_quote(log) + " 2>&1";
  const int status = std::system(cmd.c_str());
  if (status != 0) {
    r.error += "'" + cmd + "' failed (exit status " + std::to_string(status) + "); see " + log;
    return r;
  }
  const std::string html = out_dir + "/report/report.html";
  if (fs::exists(html))
    r.html = html;
  else
    r.error += "plot script ran but wrote no " + html;
  return r;
}

}  // namespace s3m::run
