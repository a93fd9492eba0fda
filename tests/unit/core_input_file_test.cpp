// The one gate in front of every reader (core/input_file.hpp) and the thread-count range
// (core/thread_count.hpp): issue 24.
#include <filesystem>
#include <fstream>
#include <thread>

#include <gtest/gtest.h>

#include "fifo_test_util.hpp"
#include "s3m/core/error.hpp"
#include "s3m/core/input_file.hpp"
#include "s3m/core/thread_count.hpp"

namespace s3m {
namespace {

namespace fs = std::filesystem;

fs::path scratch() {
  const fs::path d = fs::temp_directory_path() / ("s3m_core_input_file_" + std::to_string(::getpid()));
  fs::create_directories(d);
  return d;
}

TEST(InputFile, SaysWhatAPathIsWithoutOpeningIt) {
  const fs::path d = scratch();
  std::ofstream(d / "plain.txt") << "x";
  fs::remove(d / "link.txt");
  fs::create_symlink(d / "plain.txt", d / "link.txt");
  testing::make_fifo(d / "pipe");
  EXPECT_EQ(input_file_problem((d / "plain.txt").string()), "");
  EXPECT_EQ(input_file_problem((d / "link.txt").string()), "");  // symbolic links are followed
  EXPECT_EQ(input_file_problem((d / "missing.txt").string()), "file not found");
  EXPECT_EQ(input_file_problem(d.string()), "is a directory, not a regular file");
  EXPECT_EQ(input_file_problem((d / "pipe").string()), "is a FIFO (named pipe), not a regular file");
  EXPECT_EQ(input_file_problem("/dev/null"), "is a character device, not a regular file");
  fs::remove_all(d);
}

TEST(InputFile, OpenRefusesAFifoInsteadOfBlocking) {
  const fs::path d = scratch();
  const fs::path fifo = d / "list.txt";
  testing::make_fifo(fifo);
  const std::string e = testing::error_without_blocking(fifo, [&] { open_input_file(fifo.string(), "a TUM list"); });
  EXPECT_EQ(e, fifo.string() + ": is a FIFO (named pipe), not a regular file (expected a TUM list)");
  std::ofstream(d / "ok.txt") << "hello";
  std::string line;
  std::getline(open_input_file((d / "ok.txt").string(), "text"), line);
  EXPECT_EQ(line, "hello");
  fs::remove_all(d);
}

TEST(ThreadCount, ZeroOrOneToFourTimesTheHardwareThreads) {
  const int hw = static_cast<int>(std::thread::hardware_concurrency());
  EXPECT_EQ(max_thread_count(), hw > 0 ? 4 * hw : 16);
  EXPECT_TRUE(thread_count_ok(0));
  EXPECT_TRUE(thread_count_ok(1));
  EXPECT_TRUE(thread_count_ok(max_thread_count()));
  EXPECT_FALSE(thread_count_ok(max_thread_count() + 1));
  EXPECT_FALSE(thread_count_ok(-1));
  EXPECT_FALSE(thread_count_ok(65537));
  if (hw > 0) {
    EXPECT_EQ(thread_count_range("auto"), "0 (auto) or 1.." + std::to_string(4 * hw) + " (4 x the " +
                                              std::to_string(hw) + " hardware threads)");
  }
}

}  // namespace
}  // namespace s3m
