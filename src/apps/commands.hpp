#pragma once
// Each sub-command lives in its own cmd_<name>.cpp and registers itself on the root app.
// The callback throws s3m::Error on failure; main() turns that into a message and exit code 1
// (Interrupted: 130).
#include <filesystem>
#include <string>

#include <CLI/CLI.hpp>

#include "s3m/core/error.hpp"

namespace s3m::apps {

// A command stopped by Ctrl-C (or SIGTERM) after writing what it had: main() says so and exits 130,
// as a shell does for a process killed by SIGINT, so a script can tell it from a complete result.
struct Interrupted : Error {
  using Error::Error;
};

// A count option: a whole number >= 0 (CLI's own range check prints the largest double as the limit).
inline CLI::Validator count_option() {
  return CLI::Validator(
      [](std::string& value) -> std::string {
        const bool digits = !value.empty() && value.find_first_not_of("0123456789") == std::string::npos;
        return digits && value.size() <= 18 ? "" : "'" + value + "' is not a count (a whole number >= 0)";
      },
      "COUNT");
}

// A file argument that also takes the folder holding it under its usual name: the folder
// `s3m run --out` wrote (what a user has just seen printed as "outputs: OUT") for its map.ot or
// trajectory_camera.txt, a dataset folder for its groundtruth.txt. `missing` says what a folder
// without the file probably is.
inline CLI::Validator file_or_folder(const std::string& name, const std::string& missing) {
  return CLI::Validator(
      [name, missing](std::string& path) -> std::string {
        namespace fs = std::filesystem;
        if (!fs::is_directory(path)) return "";
        const fs::path file = fs::path(path) / name;
        if (!fs::is_regular_file(file)) return path + " is a folder without " + name + " (" + missing + ")";
        path = file.string();
        return "";
      },
      name + "|FOLDER");
}
inline CLI::Validator map_or_run_folder() { return file_or_folder("map.ot", "a --slam-only run?"); }

void register_eval(CLI::App& app);     // trajectory evaluation (ATE/RPE, plots)
void register_sim(CLI::App& app);      // synthetic RGB-D sequences
void register_run(CLI::App& app);      // full pipeline on a dataset
void register_check(CLI::App& app);    // what s3m makes of a dataset folder, before a run
void register_demo(CLI::App& app);     // simulate + run + report, no arguments
void register_segeval(CLI::App& app);  // segmentation evaluation
void register_query(CLI::App& app);    // semantic map queries
void register_plan(CLI::App& app);     // paths through a map to a class or point
void register_export(CLI::App& app);   // map export (PLY, ColorOcTree, .bt)
void register_vocab(CLI::App& app);    // bag-of-words vocabulary training
void register_tum2bag(CLI::App& app);  // TUM directory -> ROS1 bag (ROS builds)
void register_view(CLI::App& app);     // interactive 3-D map viewer (HTML)
void register_merge(CLI::App& app);    // merge saved sessions (two or more)
void register_batch(CLI::App& app);    // many recordings: runs on Slurm or locally, N-way merge

}  // namespace s3m::apps
