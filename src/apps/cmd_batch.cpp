// `s3m batch MANIFEST --out DIR --engine slurm|local`: many recordings of one building, one
// `s3m run` each, then their N-way merge and a summary (s3m::batch).
#include <chrono>
#include <filesystem>
#include <fstream>
#include <iostream>

#include "commands.hpp"
#include "s3m/batch/engines.hpp"
#include "s3m/batch/plan.hpp"
#include "s3m/batch/summary.hpp"
#include "s3m/core/error.hpp"

namespace s3m::apps {

namespace {

struct BatchArgs {
  std::string manifest, out, engine = "local";
  bool dry_run = false, wait = false, merge_stage = false;
  int jobs = 0;
};

std::string this_binary() {
  std::error_code ec;
  const auto exe = std::filesystem::read_symlink("/proc/self/exe", ec);
  if (ec) throw Error("batch: cannot find the s3m binary's own path (/proc/self/exe): " + ec.message());
  return exe.string();
}

void print_scripts(const batch::Plan& plan) {
  for (const std::string& path : plan.scripts) {
    std::ifstream in(path);
    std::cout << "### " << path << "\n" << in.rdbuf() << "\n";
  }
}

// The summary's verdict: one line per recording that is not done, then an error when any is not.
void report(const nlohmann::json& summary, const std::string& dir) {
  for (const auto& r : summary["runs"])
    std::cout << r["name"].get<std::string>() << ": " << r["status"].get<std::string>()
              << (r.contains("error") ? ": " + r["error"].get<std::string>() : "") << "\n";
  const auto& merged = summary["merged"];
  std::cout << "merged: " << merged["status"].get<std::string>();
  if (merged.contains("map") && merged["map"].contains("miou"))
    std::cout << ", mIoU " << merged["map"]["miou"] << ", coverage of the runs' union "
              << merged["map"].value("coverage_of_union", 0.0);
  std::cout << "\nsummary: " << dir << "/summary.html\n";
  if (summary["failed"].get<int>() > 0)
    throw Error("batch: " + std::to_string(summary["failed"].get<int>()) + " of " +
                std::to_string(summary["recordings"].get<int>()) + " recordings did not run (see " + dir +
                "/summary.html); s3m batch again re-runs only those");
}

void run_batch(const BatchArgs& a) {
  if (a.merge_stage) {
    const nlohmann::json s = batch::merge_stage(a.manifest, a.out);
    std::cout << "summary: " << s["dir"].get<std::string>() << "/summary.json\n";
    return;
  }
  const batch::Plan plan = batch::make_plan(a.manifest, a.out, this_binary());
  std::cout << plan.todo.size() << " of " << plan.manifest.recordings.size()
            << " recordings to run; scripts in " << plan.paths.dir << "/jobs\n";
  // A summary older than this batch is an earlier batch's: this one's merge stage did not run.
  const auto started = std::filesystem::file_time_type::clock::now() - std::chrono::seconds(1);
  if (a.engine == "local") {
    if (a.dry_run) return print_scripts(plan);
    const int rc = batch::run_local(plan, a.jobs);
    if (rc != 0)
      throw Error("batch: the merge stage failed (exit status " + std::to_string(rc) +
                  "), see its output above");
  } else {
    const batch::SlurmSubmission s = batch::submit_slurm(plan, a.wait, a.dry_run);
    if (a.dry_run) print_scripts(plan);
    for (const auto& c : s.commands) std::cout << (a.dry_run ? "would run: " : "submitted: ") << c << "\n";
    if (a.dry_run) return;
    std::cout << "array job " << (s.array_job.empty() ? "none" : s.array_job) << ", merge job " << s.merge_job
              << "\n";
    if (!a.wait) return;
  }
  const std::string summary = plan.paths.dir + "/summary.json";
  std::error_code ec;
  std::ifstream in(summary);
  if (!in || std::filesystem::last_write_time(summary, ec) < started || ec)
    throw Error("batch: the merge stage wrote no summary.json (its log: " + plan.paths.dir +
                "/logs/merge.log)");
  report(nlohmann::json::parse(in), plan.paths.dir);
}

}  // namespace

void register_batch(CLI::App& app) {
  auto a = std::make_shared<BatchArgs>();
  auto* cmd = app.add_subcommand("batch",
                                 "Run many recordings of one building (a YAML manifest) and merge them: one "
                                 "`s3m run` each as a Slurm job "
                                 "array or in a local process pool, then the N-way merge and "
                                 "DIR/summary.json + summary.html. Again on the "
                                 "same DIR: only the failed or missing recordings run");
  cmd->add_option("manifest", a->manifest,
                  "YAML: recordings (path, name, config, ...), defaults, merge (README)")
      ->required()
      ->check(CLI::ExistingFile);
  cmd->add_option("--out", a->out, "batch folder: runs/, logs/, jobs/ (the scripts), merged/, summary.*")
      ->required();
  cmd->add_option("--engine", a->engine,
                  "slurm (sbatch: job array, then the merge job) or local (process pool)")
      ->check(CLI::IsMember({"slurm", "local"}));
  cmd->add_flag("--dry-run", a->dry_run,
                "write and print the job scripts (and the sbatch commands), run nothing");
  cmd->add_flag("--wait", a->wait, "slurm: wait for the merge job, then print the summary");
  cmd->add_option("--jobs", a->jobs, "local: runs at once (default: cores / CPUs per run)")
      ->check(CLI::NonNegativeNumber);
  cmd->add_flag(
      "--merge-stage", a->merge_stage,
      "run only the merge stage (what the merge job runs): merge the runs that succeeded, write the summary");
  cmd->callback([a] { run_batch(*a); });
}

}  // namespace s3m::apps
