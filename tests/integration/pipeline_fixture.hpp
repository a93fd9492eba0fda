#pragma once
// Shared set-up of the end-to-end tests: one short simulated sequence (fixed seed) rendered once per
// test binary, and helpers to run the pipeline on it into fresh output folders.
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

#include <sys/wait.h>
#include <unistd.h>

#include <gtest/gtest.h>

#include "s3m/pipeline/pipeline_config.hpp"
#include "s3m/run/run.hpp"
#include "s3m/sim/simulate.hpp"

#include "cached_folder.hpp"

namespace s3m::it {

namespace fs = std::filesystem;

// Output folders of this process (ctest runs every test in its own process, possibly in parallel).
inline fs::path scratch_dir() {
  const fs::path d = fs::temp_directory_path() / ("s3m_integration_" + std::to_string(::getpid()));
  fs::create_directories(d);
  return d;
}

// Removes this process's output folders when the tests end.
class ScratchCleanup : public ::testing::Environment {
 public:
  void TearDown() override {
    std::error_code ec;
    fs::remove_all(scratch_dir(), ec);
  }
};

// 2 s of hand-held motion through the office at 30 Hz (fixed seed).
inline constexpr int kFrames = 60;

inline sim::SimConfig sequence_config() {
  sim::SimConfig c;
  c.scene = "office";
  c.seed = 7;
  c.trajectory.type = "handheld";
  c.trajectory.frames = kFrames;
  return c;
}

// The sequence, rendered once and cached in the temp folder for every test process (the simulator
// is deterministic; see cached_folder.hpp).
inline const std::string& sequence_dir() {
  static const std::string dir = cached_folder(
      fs::temp_directory_path() / ("s3m_it_sequence_office_handheld_seed7_" + std::to_string(kFrames)),
      "gt_voxels.txt", [](const fs::path& tmp) { sim::simulate_sequence(sequence_config(), tmp.string()); });
  return dir;
}

// The simulator preset of the repository (the tests check it is usable as shipped).
inline pipeline::PipelineConfig sim_preset() {
  return pipeline::load_pipeline_config(std::string(S3M_TEST_DATA_DIR) + "/../../config/sim.yaml");
}

inline run::RunOptions options(const std::string& out_name, bool deterministic) {
  run::RunOptions o;
  o.dataset_dir = sequence_dir();
  o.out_dir = (scratch_dir() / out_name).string();
  fs::remove_all(o.out_dir);
  o.config = sim_preset();
  o.config.threads.deterministic = deterministic;
  o.segmenter = "oracle";
  o.report = false;
  return o;
}

// A copy of a sequence (default: the fixture's) in scratch_dir()/name whose files are links to the
// sequence's (the cached sequence is never written through them), except the files for which
// skip(relative path) is true: those the caller writes.
template <typename Skip>
fs::path linked_copy(const std::string& name, Skip skip, const std::string& sequence = sequence_dir()) {
  const fs::path dir = scratch_dir() / name;
  fs::remove_all(dir);
  fs::create_directories(dir);
  const fs::path src = fs::absolute(sequence);
  for (const auto& e : fs::recursive_directory_iterator(src)) {
    const fs::path rel = fs::relative(e.path(), src);
    if (e.is_directory())
      fs::create_directories(dir / rel);
    else if (!skip(rel))
      fs::create_symlink(e.path(), dir / rel);
  }
  return dir;
}

inline std::string read_bytes(const std::string& path) {
  std::ifstream f(path, std::ios::binary);
  std::stringstream ss;
  ss << f.rdbuf();
  return ss.str();
}

// Runs the built `s3m ARGS` as a user would; returns its exit status, stdout+stderr in *log.
inline int run_s3m(const std::string& args, const fs::path& log_path, std::string* log) {
  const std::string cmd = std::string(S3M_BINARY) + " " + args + " > '" + log_path.string() + "' 2>&1";
  const int status = std::system(cmd.c_str());
  *log = read_bytes(log_path.string());
  return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
}

}  // namespace s3m::it
