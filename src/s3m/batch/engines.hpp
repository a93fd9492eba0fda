#pragma once
// The two engines that run a batch's job graph (plan.hpp): the same scripts either way.
//   local: task_<i>.sh of every planned recording in a pool of `jobs` processes, then
//          merge.sbatch with bash once they have all finished (failed or not);
//   slurm: `sbatch runs.sbatch` (the job array), then `sbatch --dependency=afterany:<array>
//          merge.sbatch`. afterany rather than afterok: a failed recording fails its array task,
//          and afterok would then never start the merge of the others.
#include <string>
#include <vector>

#include "s3m/batch/plan.hpp"

namespace s3m::batch {

// Runs the plan here; jobs <= 0: cores / CPUs per task (at least 1). Returns the merge stage's
// exit status (0: the summary was written).
int run_local(const Plan& plan, int jobs);

struct SlurmSubmission {
  std::vector<std::string> commands;  // the sbatch command lines, as run (or, dry, as they would be)
  std::string array_job, merge_job;   // job ids ("" when not submitted)
};

// Submits the plan; with wait, returns when the merge job has ended (sbatch --wait). dry: only
// says what it would submit. Throws s3m::Error with sbatch's output when a submission fails.
SlurmSubmission submit_slurm(const Plan& plan, bool wait, bool dry, const std::string& sbatch = "sbatch");

}  // namespace s3m::batch
