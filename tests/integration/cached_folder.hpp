#pragma once
// A folder the integration tests build once and share across test processes (ctest runs them in
// parallel): built into a private folder and renamed into place, so no process ever sees it half
// written. Only for content that is deterministic, so a complete cached copy equals a fresh one.
#include <cctype>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <functional>
#include <regex>
#include <string>
#include <system_error>

#include <unistd.h>

namespace s3m::it {

// The simulator's frames depend on Embree's kernels (S3M_EMBREE_CONFIG pins them, e.g. "isa=sse4.2"),
// so a run with them pinned must not reuse frames rendered with the CPU's own choice.
inline std::string render_key() {
  const char* config = std::getenv("S3M_EMBREE_CONFIG");
  if (!config || !*config) return "";
  std::string key = "_embree_";
  for (const char c : std::string(config)) key += std::isalnum(static_cast<unsigned char>(c)) ? c : '_';
  return key;
}

// Returns the cached folder, dir (plus render_key()); when its complete_marker is missing,
// build(tmp) fills a fresh private folder first.
inline std::string cached_folder(const std::filesystem::path& requested, const std::string& complete_marker,
                                 const std::function<void(const std::filesystem::path& tmp)>& build) {
  namespace fs = std::filesystem;
  const fs::path dir = requested.string() + render_key();
  if (fs::exists(dir / complete_marker)) return dir.string();
  const fs::path tmp = dir.string() + ".tmp" + std::to_string(::getpid());
  build(tmp);
  std::error_code ec;
  fs::rename(tmp, dir, ec);  // fails harmlessly when another process finished first
  if (ec) fs::remove_all(tmp, ec);
  return dir.string();
}

// Removes the copies of stamped's run that other builds of the same build folder made (stamped:
// base_<size>_<time>, see build_stamped), finished or not: they are never read again, and a session's cached
// runs are ~400 MB per build, which repeated builds would otherwise pile up in the temp folder.
inline void remove_other_builds(const std::filesystem::path& stamped, const std::string& base_name) {
  namespace fs = std::filesystem;
  static const std::regex kStamp("[0-9]+_-?[0-9]+(\\.tmp[0-9]+)?");
  const std::string own = stamped.filename().string();
  std::error_code ec;
  for (auto it = fs::directory_iterator(stamped.parent_path(), ec); !ec && it != fs::directory_iterator();
       it.increment(ec)) {
    const std::string name = it->path().filename().string();
    if (name.size() <= base_name.size() + 1 || name.compare(0, base_name.size() + 1, base_name + "_") != 0)
      continue;
    const std::string stamp = name.substr(base_name.size() + 1);
    if (!std::regex_match(stamp, kStamp) || name.compare(0, own.size(), own) == 0) continue;
    std::error_code ignored;  // another process may be removing it too
    fs::remove_all(it->path(), ignored);
  }
}

// path with this test executable's size and modification time appended: for cached *runs* of
// s3m, whose content (and file formats) change with the build. Without it a cached run made by an
// earlier build is reused, e.g. a slam_map.bin of the previous format version. Earlier builds'
// copies are removed.
inline std::filesystem::path build_stamped(const std::filesystem::path& path) {
  namespace fs = std::filesystem;
  std::error_code ec;
  const fs::path exe = fs::read_symlink("/proc/self/exe", ec);
  if (ec) return path;
  const auto size = fs::file_size(exe, ec);
  const auto time = fs::last_write_time(exe, ec).time_since_epoch().count();
  // Keyed by the build folder too: two checkouts testing at once must not remove each other's runs.
  char key[20];
  std::snprintf(key, sizeof key, "b%zx", std::hash<std::string>{}(exe.parent_path().string()));
  const fs::path base = path.string() + "_" + key;
  const fs::path stamped = base.string() + "_" + std::to_string(size) + "_" + std::to_string(time);
  remove_other_builds(stamped, base.filename().string());
  return stamped;
}

}  // namespace s3m::it
