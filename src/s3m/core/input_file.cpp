#include "s3m/core/input_file.hpp"

#include <filesystem>

#include "s3m/core/error.hpp"

namespace s3m {
namespace fs = std::filesystem;

std::string input_file_problem(const std::string& path) {
  std::error_code ec;
  const fs::file_status s = fs::status(path, ec);  // stat(), follows symlinks; never open()
  const char* kind = nullptr;
  switch (s.type()) {
    case fs::file_type::regular: return "";
    case fs::file_type::not_found: return "file not found";
    case fs::file_type::directory: kind = "a directory"; break;
    case fs::file_type::fifo: kind = "a FIFO (named pipe)"; break;
    case fs::file_type::character: kind = "a character device"; break;
    case fs::file_type::block: kind = "a block device"; break;
    case fs::file_type::socket: kind = "a socket"; break;
    default: return "cannot inspect the file (" + (ec ? ec.message() : std::string("unknown file type")) + ")";
  }
  return std::string("is ") + kind + ", not a regular file";
}

void require_input_file(const std::string& path, const std::string& what) {
  if (const std::string problem = input_file_problem(path); !problem.empty()) throw ParseError(path, 0, problem, what);
}

std::ifstream open_input_file(const std::string& path, const std::string& what, std::ios::openmode mode) {
  require_input_file(path, what);
  std::ifstream in(path, mode | std::ios::in);
  if (!in) throw ParseError(path, 0, "cannot open file for reading", what);
  return in;
}

}  // namespace s3m
