#include "s3m/pipeline/report.hpp"

#include <cstdlib>
#include <filesystem>

namespace s3m::pipeline {
namespace fs = std::filesystem;

namespace {

std::string shell_quote(const std::string& s) {
  std::string q = "'";
  for (char ch : s) q += ch == '\'' ? std::string("'\\''") : std::string(1, ch);
  return q + "'";
}

}  // namespace

std::string tools_dir() {
  if (const char* env = std::getenv("S3M_TOOLS_DIR"); env && *env) return env;
  return std::string(S3M_SOURCE_DIR) + "/tools";
}

ReportResult make_report(const std::string& out_dir) {
  ReportResult r;
  const std::string script = tools_dir() + "/plot_report.py";
  if (!fs::exists(script)) {
    r.error = "plot script " + script + " not found (set S3M_TOOLS_DIR to the repository's tools/)";
    return r;
  }
  // Debian's interpreter has numpy/matplotlib; a pyenv/venv python3 on PATH usually does not.
  const std::string python = fs::exists("/usr/bin/python3") ? "/usr/bin/python3" : "python3";
  const std::string log = out_dir + "/report/plot_report.log";
  fs::create_directories(out_dir + "/report");
  const std::string cmd = python + " " + shell_quote(script) + " " + shell_quote(out_dir) + " > " +
                          shell_quote(log) + " 2>&1";
  const int status = std::system(cmd.c_str());
  if (status != 0) {
    r.error = "'" + cmd + "' failed (exit status " + std::to_string(status) + "); see " + log;
    return r;
  }
  const std::string html = out_dir + "/report/report.html";
  if (fs::exists(html)) r.html = html;
  else r.error = "plot script ran but wrote no " + html;
  return r;
}

}  // namespace s3m::pipeline
