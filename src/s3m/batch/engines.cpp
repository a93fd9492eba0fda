// The local process pool and the Slurm submission of a batch (engines.hpp).
#include "s3m/batch/engines.hpp"

#include <array>
#include <cerrno>
#include <cstdio>
#include <cstring>
#include <deque>
#include <map>
#include <thread>

#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <spdlog/spdlog.h>

#include "s3m/core/error.hpp"

extern char** environ;

namespace s3m::batch {

namespace {

// Starts `bash script`; its output goes where this process's goes unless the script redirects it.
pid_t spawn_bash(const std::string& script) {
  std::string bash = "/bin/bash", arg0 = "bash", s = script;
  char* argv[] = {arg0.data(), s.data(), nullptr};
  pid_t pid = 0;
  const int rc = posix_spawn(&pid, bash.c_str(), nullptr, nullptr, argv, environ);
  if (rc != 0) throw Error("batch: cannot start bash " + script + ": " + std::strerror(rc));
  return pid;
}

int wait_for(pid_t pid) {
  int status = 0;
  while (waitpid(pid, &status, 0) < 0)
    if (errno != EINTR) return -1;
  return WIFEXITED(status) ? WEXITSTATUS(status) : 128 + WTERMSIG(status);
}

// Runs a shell command, returning its exit status and its standard output (stderr joined).
int capture(const std::string& command, std::string& output) {
  FILE* pipe = popen((command + " 2>&1").c_str(), "r");
  if (!pipe) throw Error("batch: cannot run '" + command + "': " + std::strerror(errno));
  std::array<char, 4096> buf{};
  std::size_t n = 0;
  while ((n = std::fread(buf.data(), 1, buf.size(), pipe)) > 0) output.append(buf.data(), n);
  const int status = pclose(pipe);
  return WIFEXITED(status) ? WEXITSTATUS(status) : 128;
}

// sbatch --parsable prints "JOBID" or "JOBID;CLUSTER".
std::string job_id(const std::string& output) {
  std::string id;
  for (const char c : output) {
    if (c == ';' || c == '\n') break;
    id += c;
  }
  return id;
}

}  // namespace

int run_local(const Plan& plan, int jobs) {
  if (jobs <= 0) jobs = std::max(1, int(std::thread::hardware_concurrency()) / std::max(1, plan.task.cpus));
  std::deque<std::size_t> queue(plan.todo.begin(), plan.todo.end());
  std::map<pid_t, std::size_t> running;
  while (!queue.empty() || !running.empty()) {
    while (!queue.empty() && int(running.size()) < jobs) {
      const std::size_t i = queue.front();
      queue.pop_front();
      spdlog::info("batch: running {} ({})", plan.manifest.recordings[i].name, plan.paths.task_script(i));
      running[spawn_bash(plan.paths.task_script(i))] = i;
    }
    int status = 0;
    const pid_t pid = waitpid(-1, &status, 0);
    if (pid < 0) {
      if (errno == EINTR) continue;
      throw Error(std::string("batch: waiting for the runs: ") + std::strerror(errno));
    }
    const auto it = running.find(pid);
    if (it == running.end()) continue;
    const int rc = WIFEXITED(status) ? WEXITSTATUS(status) : 128 + WTERMSIG(status);
    spdlog::info("batch: {} finished (exit status {})", plan.manifest.recordings[it->second].name, rc);
    running.erase(it);
  }
  spdlog::info("batch: merge stage ({})", plan.paths.merge_script());
  return wait_for(spawn_bash(plan.paths.merge_script()));
}

SlurmSubmission submit_slurm(const Plan& plan, bool wait, bool dry, const std::string& sbatch) {
  SlurmSubmission s;
  std::string dependency;
  if (!plan.todo.empty()) {
    s.commands.push_back(sbatch + " --parsable " + shell_quote(plan.paths.array_script()));
    if (!dry) {
      std::string out;
      if (capture(s.commands.back(), out) != 0)
        throw Error("batch: " + s.commands.back() + " failed: " + out);
      s.array_job = job_id(out);
      dependency = " --dependency=afterany:" + s.array_job;
    } else {
      dependency = " --dependency=afterany:ARRAY_JOB";
    }
  }
  s.commands.push_back(sbatch + " --parsable" + dependency + (wait ? " --wait " : " ") +
                       shell_quote(plan.paths.merge_script()));
  if (dry) return s;
  std::string out;
  const int rc = capture(s.commands.back(), out);
  s.merge_job = job_id(out);
  // With --wait, sbatch exits with the job's status: a failed merge stage is reported by the caller
  // from the summary (or its absence), a failed submission here.
  if (rc != 0 && (s.merge_job.empty() || !std::isdigit(static_cast<unsigned char>(s.merge_job[0]))))
    throw Error("batch: " + s.commands.back() + " failed: " + out);
  return s;
}

}  // namespace s3m::batch
