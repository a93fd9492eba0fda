// The batch job graph and its scripts (plan.hpp).
#include "s3m/batch/plan.hpp"

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <sstream>

#include <fmt/format.h>
#include <spdlog/spdlog.h>

#include "s3m/core/atomic_file.hpp"
#include "s3m/core/error.hpp"
#include "s3m/pipeline/cost_estimate.hpp"
#include "s3m/pipeline/frame_source.hpp"

namespace s3m::batch {
namespace fs = std::filesystem;

namespace {

// The process, the vocabulary (~40 MB) and a frame's images and features, measured at ~250 MB
// RSS for a 100-frame simulator run beside its kept clouds.
constexpr long kBaseMemMb = 512;

long round_up(double mb, long step) { return long(std::ceil(mb / double(step))) * step; }

std::string read_file(const std::string& path) {
  std::ifstream in(path);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

// The run's error: its "s3m: error:" line, else the log's last non-empty line.
std::string error_of(const std::string& log) {
  std::istringstream in(read_file(log));
  std::string line, last, error;
  while (std::getline(in, line)) {
    if (line.empty()) continue;
    last = line;
    for (const char* tag : {"s3m: error: ", "s3m: unexpected error: "})
      if (line.rfind(tag, 0) == 0) error = line.substr(std::string(tag).size());
  }
  return error.empty() ? last : error;
}

bool is_ros1_bag(const std::string& path) { return fs::path(path).extension() == ".bag"; }

std::string run_command(const Plan& p, const Recording& r) {
  std::string c = shell_quote(p.s3m) + " run ";
  c += is_ros1_bag(r.path) ? "--rosbag " + shell_quote(r.path) : shell_quote(r.path);
  c += " --out " + shell_quote(p.paths.run(r));
  if (!r.run.config.empty()) c += " --config " + shell_quote(r.run.config);
  if (!r.run.segmenter.empty()) c += " --segmenter " + shell_quote(r.run.segmenter);
  if (r.run.deterministic) c += " --deterministic";
  if (r.run.max_frames >= 0) c += " --max-frames " + std::to_string(r.run.max_frames);
  // The batch summary is the report; the runs write their maps and metrics only.
  return c + " --no-report --no-session-mcap";
}

std::string task_script(const Plan& p, std::size_t i) {
  const Recording& r = p.manifest.recordings[i];
  return fmt::format(
      "#!/usr/bin/env bash\n"
      "# s3m batch, recording {} '{}' ({}): one `s3m run` into {}.\n"
      "# Its output goes to {}, its exit status to {} (what a re-run of the batch reads).\n"
      "set -u\n"
      "rm -rf {} {}\n"
      "mkdir -p {} {}\n"
      "{} > {} 2>&1\n"
      "rc=$?\n"
      "echo \"$rc\" > {}\n"
      "exit \"$rc\"\n",
      i, r.name, r.path, p.paths.run(r), p.paths.log(r), p.paths.exit_file(r), shell_quote(p.paths.run(r)),
      shell_quote(p.paths.exit_file(r)), shell_quote(p.paths.dir + "/runs"),
      shell_quote(p.paths.dir + "/logs"), run_command(p, r), shell_quote(p.paths.log(r)),
      shell_quote(p.paths.exit_file(r)));
}

std::string array_script(const Plan& p) {
  std::string indices;
  for (std::size_t i : p.todo) indices += (indices.empty() ? "" : ",") + std::to_string(i);
  if (indices.empty()) indices = "none";  // never submitted: nothing to run
  return fmt::format(
      "#!/usr/bin/env bash\n"
      "# s3m batch: the recordings to run as one Slurm job array (submit: sbatch {}).\n"
      "# Request per task from the cost estimate of the largest recording.\n"
      "#SBATCH --job-name=s3m-runs\n"
      "#SBATCH --array={}\n"
      "#SBATCH --cpus-per-task={}\n"
      "#SBATCH --mem={}M\n"
      "#SBATCH --output={}/logs/slurm-runs-%A_%a.out\n"
      "exec bash {}/jobs/task_\"${{SLURM_ARRAY_TASK_ID}}\".sh\n",
      p.paths.array_script(), indices, p.task.cpus, p.task.mem_mb, p.paths.dir, shell_quote(p.paths.dir));
}

std::string merge_script(const Plan& p) {
  return fmt::format(
      "#!/usr/bin/env bash\n"
      "# s3m batch: the merge stage, after every run (submit: sbatch --dependency=afterany:ARRAY_JOB {}; or\n"
      "# run it with bash): the runs that succeeded merged into {}, {}/summary.json and summary.html.\n"
      "#SBATCH --job-name=s3m-merge\n"
      "#SBATCH --cpus-per-task=1\n"
      "#SBATCH --mem={}M\n"
      "#SBATCH --output={}/logs/merge.log\n"
      "exec {} batch {} --out {} --merge-stage\n",
      p.paths.merge_script(), p.paths.merged(), p.paths.dir, p.merge.mem_mb, p.paths.dir, shell_quote(p.s3m),
      shell_quote(p.manifest.file), shell_quote(p.paths.dir));
}

void write_script(const std::string& path, const std::string& text) {
  write_text_atomic(path, text);
  fs::permissions(path, fs::perms::owner_exec | fs::perms::group_exec | fs::perms::others_exec,
                  fs::perm_options::add);
}

}  // namespace

std::string shell_quote(const std::string& s) {
  std::string out = "'";
  for (const char c : s) out += c == '\'' ? std::string("'\\''") : std::string(1, c);
  return out + "'";
}

const char* to_string(RunState s) {
  switch (s) {
    case RunState::kDone: return "done";
    case RunState::kFailed: return "failed";
    case RunState::kNotFinished: return "not finished";
    case RunState::kNotStarted: return "not started";
  }
  return "?";
}

Resources estimate_resources(const Recording& r) {
  Resources out;
  try {
    const pipeline::PipelineConfig config =
        r.run.config.empty() ? pipeline::PipelineConfig{} : pipeline::load_pipeline_config(r.run.config);
    out.cpus =
        r.run.deterministic || config.threads.deterministic ? 1 : 4;  // tracking, segmentation, mapping, BA
    if (!fs::is_directory(r.path) || is_ros1_bag(r.path)) return out;
    const auto source = pipeline::open_tum_source(r.path, config.dataset);
    const pipeline::CostEstimate e = pipeline::estimate_cost(config, source->camera());
    double frames = double(source->size());
    if (r.run.max_frames >= 0) frames = std::min(frames, double(r.run.max_frames));
    double clouds_mb = frames * e.cloud_bytes / 1e6;
    if (config.cloud.kept_clouds_budget_mb > 0)
      clouds_mb = std::min(clouds_mb, config.cloud.kept_clouds_budget_mb);
    // One frame's map updates at ~20 B of RSS each in a room (cost_estimate.cpp).
    out.mem_mb = round_up(double(kBaseMemMb) + clouds_mb + e.voxel_updates * 20 / 1e6, 128);
  } catch (const Error& e) {
    spdlog::warn("batch: {}: no cost estimate ({}); its task asks for the base request", r.name, e.what());
  }
  return out;
}

RunStatus read_status(const Paths& paths, const Recording& r) {
  RunStatus s;
  const bool has_log = fs::exists(paths.log(r));
  if (!fs::exists(paths.exit_file(r))) {
    s.state = has_log ? RunState::kNotFinished : RunState::kNotStarted;
    if (has_log)
      s.error = "no exit status (the task was killed, or is still running; a Slurm task's own output is in " +
                paths.dir + "/logs/slurm-runs-*.out): " + error_of(paths.log(r));
    return s;
  }
  std::istringstream(read_file(paths.exit_file(r))) >> s.exit_code;
  if (s.exit_code == 0 && fs::exists(paths.run(r) + "/metrics.json")) {
    s.state = RunState::kDone;
    return s;
  }
  s.state = RunState::kFailed;
  s.error = s.exit_code == 0 ? "exit status 0 but no metrics.json" : error_of(paths.log(r));
  if (s.error.empty()) s.error = "exit status " + std::to_string(s.exit_code);
  return s;
}

Plan make_plan(const std::string& manifest, const std::string& dir, const std::string& s3m) {
  Plan p;
  p.manifest = load_manifest(manifest);
  require(fs::path(s3m).is_absolute() && fs::is_regular_file(s3m),
          "batch: the s3m binary '" + s3m + "' is not an absolute path to a file");
  p.s3m = s3m;
  std::error_code ec;
  // logs/ before anything is submitted: Slurm opens the tasks' output files there.
  for (const char* sub : {"jobs", "logs"}) {
    fs::create_directories(fs::path(dir) / sub, ec);
    if (ec) throw Error("batch: cannot create '" + (fs::path(dir) / sub).string() + "': " + ec.message());
  }
  p.paths.dir = fs::canonical(dir).string();
  long clouds_mb = 0;
  for (std::size_t i = 0; i < p.manifest.recordings.size(); ++i) {
    const Recording& r = p.manifest.recordings[i];
    const Resources need = estimate_resources(r);
    clouds_mb += need.mem_mb - kBaseMemMb;
    if (read_status(p.paths, r).state == RunState::kDone) continue;
    p.todo.push_back(i);
    p.task.cpus = std::max(p.task.cpus, need.cpus);
    p.task.mem_mb = std::max(p.task.mem_mb, need.mem_mb);
  }
  // The merge holds every run's kept clouds and SLAM map at once.
  p.merge.mem_mb = round_up(double(kBaseMemMb + clouds_mb), 128);
  for (std::size_t i = 0; i < p.manifest.recordings.size(); ++i) {
    p.scripts.push_back(p.paths.task_script(i));
    write_script(p.scripts.back(), task_script(p, i));
  }
  write_script(p.paths.array_script(), array_script(p));
  write_script(p.paths.merge_script(), merge_script(p));
  p.scripts.push_back(p.paths.array_script());
  p.scripts.push_back(p.paths.merge_script());
  return p;
}

}  // namespace s3m::batch
