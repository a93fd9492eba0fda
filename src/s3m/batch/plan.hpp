#pragma once
// The job graph of `s3m batch MANIFEST --out DIR`: one `s3m run` per recording, then the merge
// stage (`s3m batch MANIFEST --out DIR --merge-stage`: the N-way merge of the runs that succeeded,
// the evaluation and the summary). Written as shell scripts into DIR/jobs/ that both engines run,
// so a user can read them and submit them by hand:
//   task_<i>.sh     recording i (manifest order, from 0): its run into DIR/runs/<name>/, its output
//                   into DIR/logs/<name>.log, its exit status into DIR/logs/<name>.exit
//   runs.sbatch     the Slurm job array over the recordings to run (its #SBATCH lines: the CPU and
//                   memory request from the cost estimate), each array task running task_<i>.sh
//   merge.sbatch    the merge stage (a plain shell script too; Slurm runs it after the array)
// A recording whose run finished with status 0 and wrote metrics.json is done; a re-run of the
// batch plans only the others (failed, or never finished).
#include <string>
#include <vector>

#include "s3m/batch/manifest.hpp"

namespace s3m::batch {

struct Resources {
  int cpus = 1;
  long mem_mb = 1024;
};

// One `s3m run`'s request: 1 CPU when deterministic, else the pipeline's threads; memory: a base
// for the process, the vocabulary and one frame's buffers, plus the kept clouds at their estimated
// size (pipeline::estimate_cost's cloud_bytes per frame, up to cloud.kept_clouds_budget_mb) and the
// map's one-frame working set. Recordings that cannot be opened get the base request (their run fails
// in its task, with its error).
Resources estimate_resources(const Recording& r);

enum class RunState { kDone, kFailed, kNotFinished, kNotStarted };
const char* to_string(RunState s);

struct RunStatus {
  RunState state = RunState::kNotStarted;
  int exit_code = -1;
  std::string error;  // the run's "s3m: error: ..." line (or its log's last line)
};

struct Paths {
  std::string dir;  // absolute DIR
  std::string run(const Recording& r) const { return dir + "/runs/" + r.name; }
  std::string log(const Recording& r) const { return dir + "/logs/" + r.name + ".log"; }
  std::string exit_file(const Recording& r) const { return dir + "/logs/" + r.name + ".exit"; }
  std::string task_script(std::size_t i) const { return dir + "/jobs/task_" + std::to_string(i) + ".sh"; }
  std::string array_script() const { return dir + "/jobs/runs.sbatch"; }
  std::string merge_script() const { return dir + "/jobs/merge.sbatch"; }
  std::string merged() const { return dir + "/merged"; }
};

RunStatus read_status(const Paths& paths, const Recording& r);

struct Plan {
  Manifest manifest;
  Paths paths;
  std::string s3m;                // absolute path of the s3m binary the scripts call
  std::vector<std::size_t> todo;  // recordings to run: not done
  Resources task;                 // every array task's request (the largest recording's)
  Resources merge;
  std::vector<std::string> scripts;  // the files written, task scripts first
};

// Reads the manifest and DIR's state, writes DIR/jobs/. Throws s3m::Error when DIR cannot be
// written or the s3m binary is not an absolute path to a file.
Plan make_plan(const std::string& manifest, const std::string& dir, const std::string& s3m);

// Single-quoted for a POSIX shell.
std::string shell_quote(const std::string& s);

}  // namespace s3m::batch
