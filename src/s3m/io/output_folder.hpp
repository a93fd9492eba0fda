#pragma once
// Output folders named on the command line, checked before any work: a bad --out must cost nothing.
#include <string>
#include <vector>

namespace s3m::io {

// Refused (s3m::Error naming option and path) when path is an existing file: creating the folder
// would fail halfway through the work otherwise. Creates nothing.
void require_folder_path(const std::string& path, const std::string& option);
// The same check, then the folder and its parents are created; a folder that cannot be created is
// refused naming option, path and the reason.
void create_output_folder(const std::string& path, const std::string& option);

// A command's outputs are written into a hidden folder inside the destination and moved in only
// when the command succeeded: a failure before commit() (a full disk, an exception, nothing to
// write) leaves the destination's earlier contents exactly as they were. The staging folder lives
// inside the destination so that moving in is a rename on one file system, never a copy.
class StagedFolder {
 public:
  // Creates dest (and parents) when missing and the staging folder in it; a leftover staging
  // folder of a command that was killed is removed. Throws as create_output_folder.
  StagedFolder(std::string dest, const std::string& option);
  // Without commit(): the staging folder goes, and dest too when this created it.
  ~StagedFolder();
  StagedFolder(const StagedFolder&) = delete;
  StagedFolder& operator=(const StagedFolder&) = delete;

  const std::string& path() const { return staging_; }  // write the outputs here
  const std::string& dest() const { return dest_; }
  bool created_dest() const { return created_dest_; }

  // Moves every entry of the staging folder into dest, replacing the same names (a folder is
  // replaced whole), then removes the entries of `owned` this command did not produce this time:
  // an earlier run's map beside a new --slam-only trajectory would be read as this run's. Entries
  // of dest that are neither staged nor owned (the user's own files) are left alone. Returns the
  // owned entries removed.
  std::vector<std::string> commit(const std::vector<std::string>& owned);

 private:
  std::string dest_, staging_;
  bool created_dest_ = false, committed_ = false;
};

}  // namespace s3m::io
