#pragma once
// A folder the integration tests build once and share across test processes (ctest runs them in
// parallel): built into a private folder and renamed into place, so no process ever sees it half
// written. Only for content that is deterministic, so a complete cached copy equals a fresh one.
#include <filesystem>
#include <functional>
#include <string>
#include <system_error>

#include <unistd.h>

namespace s3m::it {

// Returns dir; when dir/complete_marker is missing, build(tmp) fills a fresh private folder first.
inline std::string cached_folder(const std::filesystem::path& dir, const std::string& complete_marker,
                                 const std::function<void(const std::filesystem::path& tmp)>& build) {
  namespace fs = std::filesystem;
  if (fs::exists(dir / complete_marker)) return dir.string();
  const fs::path tmp = dir.string() + ".tmp" + std::to_string(::getpid());
  build(tmp);
  std::error_code ec;
  fs::rename(tmp, dir, ec);  // fails harmlessly when another process finished first
  if (ec) fs::remove_all(tmp, ec);
  return dir.string();
}

// path with this test executable's size and modification time appended: for cached *runs* of
// s3m, whose content (and file formats) change with the build. Without it a cached run made by an
// earlier build is reused, e.g. a slam_map.bin of the previous format version.
inline std::filesystem::path build_stamped(const std::filesystem::path& path) {
  namespace fs = std::filesystem;
  std::error_code ec;
  const fs::path exe = fs::read_symlink("/proc/self/exe", ec);
  if (ec) return path;
  const auto size = fs::file_size(exe, ec);
  const auto time = fs::last_write_time(exe, ec).time_since_epoch().count();
  return path.string() + "_" + std::to_string(size) + "_" + std::to_string(time);
}

}  // namespace s3m::it
