#pragma once
// The cached runs of the session tests (issue 23) on the flights of session_sim_fixture.hpp, each
// made once and shared across test processes (cached_folder.hpp; build-stamped, so a new build
// makes them again). ctest builds them all in one fixture test first (SessionFixture, see
// tests/CMakeLists.txt): the SessionMap and MergeSession tests each need several of them, and two
// test processes starting together would otherwise both make the same run.
#include <filesystem>
#include <string>

#include "pipeline_fixture.hpp"
#include "s3m/run/run.hpp"
#include "session_sim_fixture.hpp"

namespace s3m::it {

// A deterministic run of the simulator preset, without the report.
inline run::RunOptions session_run_options(const std::string& dataset, const std::string& out) {
  run::RunOptions o;
  o.dataset_dir = dataset;
  o.out_dir = out;
  o.config = sim_preset();
  o.config.threads.deterministic = true;
  o.report = false;
  return o;
}

// SessionMap: the SLAM map is under test (kept clouds: PipelineSessionClouds).
inline run::RunOptions session_options(const std::string& dataset, const std::string& out) {
  run::RunOptions o = session_run_options(dataset, out);
  o.slam_only = true;
  return o;
}

// Run A of the SessionMap tests (SLAM only).
inline const std::string& run_a_dir() {
  static const std::string d =
      cached_folder(build_stamped(std::filesystem::temp_directory_path() / "s3m_it_session_run_a"),
                    "slam_map.bin", [](const std::filesystem::path& tmp) {
                      run::run_dataset(session_options(flight_a_dir(), tmp.string()));
                    });
  return d;
}

// MergeSession: the semantic maps are under test too (oracle labels).
inline run::RunOptions merge_run_options(const std::string& dataset, const std::string& out) {
  run::RunOptions o = session_run_options(dataset, out);
  o.segmenter = "oracle";
  return o;
}

// map_dir: the session the run continues in; max_frames < 0: all frames.
inline std::string cached_merge_run(const std::string& name, const std::string& dataset,
                                    const std::string& map_dir = "", long max_frames = -1) {
  return cached_folder(build_stamped(std::filesystem::temp_directory_path() / ("s3m_it_merge_" + name)),
                       "metrics.json", [&](const std::filesystem::path& tmp) {
                         run::RunOptions o = merge_run_options(dataset, tmp.string());
                         o.map_dir = map_dir;
                         o.max_frames = max_frames;
                         run::run_dataset(o);
                       });
}
inline const std::string& run_a() {
  static const std::string d = cached_merge_run("run_a", flight_a_dir());
  return d;
}
inline const std::string& run_c() {
  static const std::string d = cached_merge_run("run_c", flight_c_dir());
  return d;
}
inline const std::string& run_c_in_a() {
  static const std::string d = cached_merge_run("run_c_in_a", flight_c_dir(), run_a());
  return d;
}

}  // namespace s3m::it
