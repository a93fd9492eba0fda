#pragma once
// ROS 2 recordings of one short simulated sequence, written by tests/ros2/write_rosbag2.js with
// independent implementations of MCAP, CDR and rosbag2's SQLite layout (@mcap/core,
// @foxglove/rosmsg2-serialization, sql.js), and cached in the temp folder for every test process.
// Without Node.js or those npm packages (scripts/setup.sh runs `npm ci` in tests/ros2) the tests
// using them are skipped, not passed.
#include <cstdlib>
#include <filesystem>
#include <functional>
#include <string>

#include <gtest/gtest.h>

#include "cached_folder.hpp"
#include "pipeline_fixture.hpp"

namespace s3m::it {

// 40 frames of 320x240 (the default trajectory, fixed seed): ~1 MB per frame uncompressed.
inline const std::string& small_sequence_dir() {
  static const std::string dir =
      cached_folder(fs::temp_directory_path() / "s3m_it_ros2_sequence_320x240_40", "gt_voxels.txt",
                    [](const fs::path& tmp) {
                      std::string log;
                      if (run_s3m("sim --out '" + tmp.string() + "' --frames 40 --width 320 --height 240",
                                  tmp.string() + ".log", &log) != 0)
                        throw std::runtime_error("s3m sim failed: " + log);
                      fs::remove(tmp.string() + ".log");
                    });
  return dir;
}

// "" when the reference writer can run, else why not.
inline std::string reference_writer_missing() {
  const fs::path dir = fs::path(S3M_SOURCE_DIR) / "tests" / "ros2";
  if (std::system("node --version > /dev/null 2>&1") != 0) return "node (Node.js) is not installed";
  for (const char* m :
       {"@mcap/core", "@foxglove/rosmsg2-serialization", "sql.js", "lz4js", "@foxglove/wasm-zstd", "pngjs"})
    if (!fs::exists(dir / "node_modules" / m))
      return std::string("npm package ") + m + " is missing (cd tests/ros2 && npm ci)";
  return "";
}

#define S3M_REQUIRE_REFERENCE_WRITER()                                           \
  do {                                                                           \
    const std::string missing = ::s3m::it::reference_writer_missing();           \
    if (!missing.empty()) GTEST_SKIP() << "ROS 2 reference writer: " << missing; \
  } while (0)

// The sequence as `name` (e.g. "zstd.mcap", a folder name with --split) written with `options`.
inline std::string recording(const std::string& name, const std::string& options) {
  // Keyed by the writer's source, so a changed writer never reuses recordings of the old one.
  const fs::path src = fs::path(S3M_SOURCE_DIR) / "tests" / "ros2";
  const std::size_t key = std::hash<std::string>{}(read_bytes((src / "write_rosbag2.js").string()) +
                                                   read_bytes((src / "msg_definitions.js").string()));
  const fs::path dir =
      fs::temp_directory_path() / ("s3m_it_ros2_recordings_" + std::to_string(key) + render_key());
  fs::create_directories(dir);
  const fs::path path = dir / name;
  if (fs::exists(path)) return path.string();
  const fs::path tmp = dir / (name + ".tmp" + std::to_string(::getpid()));
  const std::string script = (src / "write_rosbag2.js").string();
  const std::string cmd = "node '" + script + "' --tum '" + small_sequence_dir() + "' --out '" +
                          tmp.string() + "' " + options + " > '" + tmp.string() + ".log' 2>&1";
  if (std::system(cmd.c_str()) != 0)
    throw std::runtime_error("write_rosbag2.js failed: " + read_bytes(tmp.string() + ".log"));
  fs::remove(tmp.string() + ".log");
  std::error_code ec;
  fs::rename(tmp, path, ec);  // fails harmlessly when another process finished first
  if (ec) fs::remove_all(tmp, ec);
  return path.string();
}

}  // namespace s3m::it
