#pragma once
// The ros2msg text of the message types s3m writes, with their dependencies appended as
// `ros2 bag record` stores them in MCAP schemas (readers such as Foxglove decode by it).
#include <string>

namespace s3m::rosbag2 {

// Throws s3m::Error for a type s3m does not write.
const std::string& message_definition(const std::string& type);

}  // namespace s3m::rosbag2
