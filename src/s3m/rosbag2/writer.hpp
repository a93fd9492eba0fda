#pragma once
// A ROS 2 recording written by s3m: one MCAP file (zstd chunks, message indexes and a summary, as
// `ros2 bag record` writes them) or one rosbag2 SQLite file. Messages are CDR (cdr_writer.hpp).
// The file appears under its name only when close() succeeds (written beside it, then renamed).
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

namespace s3m::rosbag2 {

class RecordingWriter {
 public:
  virtual ~RecordingWriter() = default;
  // A topic of a ROS 2 type with a known definition (msg_definitions.hpp); returns its id.
  virtual int add_topic(const std::string& topic, const std::string& type) = 0;
  // log_time_ns: the recording's time of the message (rosbag2's receive time) [ns].
  virtual void write(int topic, std::int64_t log_time_ns, const std::vector<std::uint8_t>& cdr) = 0;
  virtual void close() = 0;
};

// Throw s3m::Error naming the file when it cannot be written.
std::unique_ptr<RecordingWriter> create_mcap(const std::string& path,
                                             const std::string& compression = "zstd");
std::unique_ptr<RecordingWriter> create_db3(const std::string& path);

}  // namespace s3m::rosbag2
