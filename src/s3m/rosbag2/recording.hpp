#pragma once
// A rosbag2 recording as `ros2 bag record` leaves it: a folder with metadata.yaml and one or more
// split storage files, or a single .mcap or .db3 file. Read without ROS 2 (storage.hpp).
#include <memory>
#include <string>
#include <vector>

#include "s3m/rosbag2/storage.hpp"

namespace s3m::rosbag2 {

// Whether path names a rosbag2 recording (by name: a .mcap or .db3 file, or a folder holding
// metadata.yaml), so `s3m run PATH` reads it as one rather than as a dataset folder.
bool is_recording(const std::string& path);

class Recording {
 public:
  // Throws s3m::Error naming the file: missing, unknown storage, a metadata.yaml that lists no
  // file or one that is not there, file-level compression (not supported), a storage file's own errors.
  explicit Recording(const std::string& path);

  // Every message of every split file, file by file (MessageRef::file says which).
  void scan(const MessageVisitor& visit);
  std::vector<std::uint8_t> read(const MessageRef& ref) const;
  // The storage file and place of a message, for errors: "rec/rec_0.mcap: messages row 8".
  std::string locate(const MessageRef& ref) const;
  const std::string& path() const { return path_; }
  // "MCAP", "SQLite" or "MCAP, 3 split files", for people.
  std::string storage() const { return storage_; }

 private:
  std::string path_, storage_;
  std::vector<std::unique_ptr<StorageFile>> files_;
};

}  // namespace s3m::rosbag2
