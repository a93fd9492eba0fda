#pragma once
// The visual report of a run: PNG plots and OUT/report/report.html, drawn by tools/plot_report.py
// with Debian's matplotlib (see that script for why matplotlib).
#include <string>

namespace s3m::run {

struct ReportResult {
  std::string html;   // path of report.html when made
  std::string error;  // why not, otherwise (missing python3/matplotlib/script, script failure)
};

// Runs the plot script on out_dir (which must hold metrics.json). Never throws: a missing report
// must not lose the run's other outputs; the reason is returned instead.
ReportResult make_report(const std::string& out_dir);

}  // namespace s3m::run
