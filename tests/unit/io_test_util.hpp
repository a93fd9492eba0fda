#pragma once
// Helpers for io/eval tests: a fresh temporary directory per test and small file writers.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include <unistd.h>

#include "s3m/core/error.hpp"

namespace s3m::testing {

// Folders made by fresh_temp_dir(), removed when the test process exits (RAII: a function-local
// static's destructor), so no s3m_test_* folder is left in /tmp after a passing or failing test.
class TempDirs {
 public:
  TempDirs() = default;
  TempDirs(const TempDirs&) = delete;
  TempDirs& operator=(const TempDirs&) = delete;
  ~TempDirs() {
    std::error_code ignore;
    for (const auto& d : dirs_) std::filesystem::remove_all(d, ignore);
  }
  void add(const std::filesystem::path& dir) { dirs_.push_back(dir); }

 private:
  std::vector<std::filesystem::path> dirs_;
};

inline TempDirs& temp_dirs() {
  static TempDirs dirs;
  return dirs;
}

// An empty folder private to the current test (and process), removed at exit.
inline std::filesystem::path fresh_temp_dir() {
  const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
  const auto dir = std::filesystem::temp_directory_path() /
                   (std::string("s3m_test_") + info->test_suite_name() + "_" + info->name() + "_" +
                    std::to_string(::getpid()));
  std::filesystem::remove_all(dir);
  std::filesystem::create_directories(dir);
  temp_dirs().add(dir);
  return dir;
}

inline std::string write_file(const std::filesystem::path& path, const std::string& content) {
  std::filesystem::create_directories(path.parent_path());
  std::ofstream(path) << content;
  return path.string();
}

// Runs f, expects an s3m::Error whose message contains every fragment; returns the message.
template <typename F>
std::string expect_error(F&& f, std::initializer_list<std::string> fragments) {
  try {
    f();
  } catch (const Error& e) {
    const std::string msg = e.what();
    for (const auto& frag : fragments) EXPECT_NE(msg.find(frag), std::string::npos) << "message: " << msg << "\nmissing: " << frag;
    return msg;
  }
  ADD_FAILURE() << "expected an s3m::Error";
  return {};
}

}  // namespace s3m::testing
