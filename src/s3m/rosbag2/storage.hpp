#pragma once
// One storage file of a rosbag2 recording (an MCAP file or a SQLite .db3), read as a stream of
// messages: scan() visits every message once in file order, holding one record (MCAP: one chunk)
// at a time, and read() fetches one message again later by its MessageRef. A reader keeps
// MessageRefs, not messages, so memory stays bounded whatever the recording's size.
#include <cstdint>
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "s3m/rosbag2/bytes.hpp"

namespace s3m::rosbag2 {

struct Channel {
  std::string topic;     // "/camera/color/image_raw"
  std::string type;      // ROS 2 message type, "sensor_msgs/msg/Image" ("" when the file names none)
  std::string encoding;  // serialisation: "cdr" for ROS 2 messages
};

// Where a message is, to read it again. Opaque outside the storage classes.
struct MessageRef {
  std::uint64_t offset =
      0;  // MCAP: file offset of its chunk record, or of its data when unchunked; db3: row id
  std::uint64_t inner = 0;  // MCAP in a chunk: offset of its data in the decompressed records
  std::uint32_t size = 0;   // data bytes
  std::uint32_t file = 0;   // which file of a split recording (Recording)
  bool chunked = false;
};

struct MessageView {
  const Channel* channel = nullptr;
  std::int64_t log_time_ns = 0;  // when the recorder received it (not the header stamp)
  Bytes data;                    // the serialised message; valid during the visit only
  MessageRef ref;
};

using MessageVisitor = std::function<void(const MessageView&)>;

class StorageFile {
 public:
  virtual ~StorageFile() = default;
  // Visits every message in file order. Throws s3m::Error naming the file and the record or row
  // (and its byte offset) on a truncated or corrupt file.
  virtual void scan(const MessageVisitor& visit) = 0;
  // The data of a message scan() visited. Thread-safe.
  virtual std::vector<std::uint8_t> read(const MessageRef& ref) const = 0;
  virtual const std::string& path() const = 0;
  // Where a message is, for errors: "message at byte 123 of the chunk at byte 4567", "messages row 8".
  virtual std::string locate(const MessageRef& ref) const = 0;
};

// MCAP (mcap_file.cpp) and SQLite (db3_file.cpp). Throw s3m::Error naming the file when it is
// missing or not of that format (bad magic; not a rosbag2 database).
std::unique_ptr<StorageFile> open_mcap(const std::string& path);
std::unique_ptr<StorageFile> open_db3(const std::string& path);

}  // namespace s3m::rosbag2
