#include "s3m/io/output_folder.hpp"

#include <algorithm>
#include <filesystem>
#include <system_error>

#include "s3m/core/error.hpp"

#include <unistd.h>

namespace fs = std::filesystem;

namespace s3m::io {

void require_folder_path(const std::string& path, const std::string& option) {
  std::error_code ec;
  if (fs::exists(path, ec) && !fs::is_directory(path, ec))
    throw Error(option + " '" + path + "' is a file, not a folder: give a folder to write into");
}

void create_output_folder(const std::string& path, const std::string& option) {
  require_folder_path(path, option);
  std::error_code ec;
  fs::create_directories(path, ec);  // filesystem_error is no s3m::Error: report it as one
  if (ec || !fs::is_directory(path))
    throw Error(option + ": cannot create the output directory '" + path +
                "': " + (ec ? ec.message() : "it is not a folder") + " (expected a writable folder)");
}

namespace {

constexpr const char* kStagingPrefix = ".s3m-staging-";

bool is_staging_name(const std::string& name) { return name.rfind(kStagingPrefix, 0) == 0; }

// Entries (file or folder) are replaced by rename: a folder over a non-empty folder needs the old
// one out of the way first, renamed aside so a failure in between loses nothing.
void move_into(const fs::path& from, const fs::path& to) {
  std::error_code ec;
  if (fs::is_directory(to, ec) && !fs::is_symlink(to, ec)) {
    const fs::path aside = to.parent_path() / (std::string(kStagingPrefix) + "old-" + to.filename().string());
    fs::remove_all(aside, ec);
    fs::rename(to, aside, ec);
    if (ec) throw Error("cannot replace '" + to.string() + "': " + ec.message());
    fs::rename(from, to, ec);
    if (ec) {
      std::error_code ignored;
      fs::rename(aside, to, ignored);
      throw Error("cannot move '" + from.string() + "' to '" + to.string() + "': " + ec.message());
    }
    fs::remove_all(aside, ec);
    return;
  }
  fs::rename(from, to, ec);
  if (ec) throw Error("cannot move '" + from.string() + "' to '" + to.string() + "': " + ec.message());
}

}  // namespace

StagedFolder::StagedFolder(std::string dest, const std::string& option) : dest_(std::move(dest)) {
  std::error_code ec;
  created_dest_ = !fs::exists(dest_, ec);
  create_output_folder(dest_, option);
  for (const auto& e : fs::directory_iterator(dest_, ec))
    if (is_staging_name(e.path().filename().string())) fs::remove_all(e.path(), ec);
  staging_ = (fs::path(dest_) / (std::string(kStagingPrefix) + std::to_string(::getpid()))).string();
  fs::create_directory(staging_, ec);
  if (ec)
    throw Error(option + ": cannot create the staging folder '" + staging_ + "': " + ec.message() +
                " (expected a writable folder)");
}

StagedFolder::~StagedFolder() {
  std::error_code ec;
  fs::remove_all(staging_, ec);
  if (!committed_ && created_dest_ && fs::is_empty(dest_, ec)) fs::remove(dest_, ec);
}

std::vector<std::string> StagedFolder::commit(const std::vector<std::string>& owned) {
  std::vector<fs::path> staged;
  std::error_code ec;
  for (const auto& e : fs::directory_iterator(staging_)) staged.push_back(e.path());
  // metrics.json last: a folder whose metrics.json is new holds a complete new run.
  std::stable_partition(staged.begin(), staged.end(),
                        [](const fs::path& p) { return p.filename() != "metrics.json"; });
  std::vector<std::string> names;
  for (const fs::path& p : staged) {
    move_into(p, fs::path(dest_) / p.filename());
    names.push_back(p.filename().string());
  }
  std::vector<std::string> removed;
  for (const std::string& name : owned) {
    if (std::find(names.begin(), names.end(), name) != names.end()) continue;
    const fs::path old = fs::path(dest_) / name;
    if (fs::exists(fs::symlink_status(old, ec)) && fs::remove_all(old, ec) > 0)
      removed.push_back(old.string());
  }
  fs::remove_all(staging_, ec);
  committed_ = true;
  return removed;
}

}  // namespace s3m::io
