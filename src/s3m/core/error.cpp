#include "s3m/core/error.hpp"

#include <sstream>

namespace s3m {
namespace {
std::string format_parse_error(const std::string& file, int line, const std::string& problem,
                               const std::string& expected) {
  // ostringstream rather than string += : GCC 12 emits a false -Wrestrict on the latter.
  std::ostringstream msg;
  msg << file;
  if (line > 0) msg << ':' << line;
  msg << ": " << problem;
  if (!expected.empty()) msg << " (expected " << expected << ')';
  return msg.str();
}
}  // namespace

ParseError::ParseError(std::string file, int line, const std::string& problem, const std::string& expected)
    : Error(format_parse_error(file, line, problem, expected)), file_(std::move(file)), line_(line) {}

void require(bool cond, const std::string& what) {
  if (!cond) throw Error(what);
}

}  // namespace s3m
