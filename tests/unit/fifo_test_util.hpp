#pragma once
// Tests that a reader refuses a FIFO (named pipe) without hanging when it does not: a reader that
// opens a FIFO blocks until a writer appears, so the read runs on another thread with a timeout,
// and on timeout the test fails and opens the write end itself until the reader gets end-of-file.
#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <chrono>
#include <exception>
#include <filesystem>
#include <functional>
#include <future>
#include <string>

#include <gtest/gtest.h>

namespace s3m::testing {

// Makes a FIFO at path (replacing any file there); fails the test if mkfifo fails.
inline void make_fifo(const std::filesystem::path& path) {
  std::filesystem::remove(path);
  ASSERT_EQ(::mkfifo(path.c_str(), 0600), 0) << "mkfifo " << path;
}

// Runs read() on another thread and returns the what() of the exception it throws, or
// "(no exception)". If read() is still running after timeout it fails the test, then unblocks it.
inline std::string error_without_blocking(const std::filesystem::path& fifo, const std::function<void()>& read,
                                          std::chrono::seconds timeout = std::chrono::seconds(10)) {
  auto result = std::async(std::launch::async, [&]() -> std::string {
    try {
      read();
    } catch (const std::exception& e) {
      return e.what();
    }
    return "(no exception)";
  });
  if (result.wait_for(timeout) == std::future_status::timeout) {
    ADD_FAILURE() << "reading " << fifo << " still blocked after " << timeout.count()
                  << " s: the reader opened the FIFO instead of refusing it";
    // A writer that opens and closes the FIFO hands the blocked reader end-of-file (repeated, as a
    // reader may open the path again).
    while (result.wait_for(std::chrono::milliseconds(20)) == std::future_status::timeout) {
      const int fd = ::open(fifo.c_str(), O_WRONLY | O_NONBLOCK);
      if (fd >= 0) ::close(fd);
    }
  }
  return result.get();
}

}  // namespace s3m::testing
