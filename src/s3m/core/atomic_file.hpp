#pragma once
// Crash-safe file output (in core so that every module can use it; s3m/io/atomic_file.hpp re-exports it): readers never see a half-written file. The content goes to a temporary
// file in the same directory, is flushed and fsync'ed, then renamed over the target (atomic on POSIX).
#include <functional>
#include <ostream>
#include <string>
#include <vector>

namespace s3m {

// writer fills the stream (opened in binary mode). Throws s3m::Error naming path on any failure
// (missing directory, disk full, writer exception); the temporary file is removed on failure.
void write_file_atomic(const std::string& path, const std::function<void(std::ostream&)>& writer);
void write_text_atomic(const std::string& path, const std::string& content);
void write_bytes_atomic(const std::string& path, const std::vector<unsigned char>& bytes);

}  // namespace s3m
