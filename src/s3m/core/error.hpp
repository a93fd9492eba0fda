#pragma once
// Errors: one exception type with context, so every message a user sees names what went wrong,
// where (file, line) and what was expected. Library code never calls exit().
#include <stdexcept>
#include <string>

namespace s3m {

class Error : public std::runtime_error {
 public:
  explicit Error(const std::string& what) : std::runtime_error(what) {}
};

// A malformed input file. Message format: "<file>:<line>: <problem> (expected <expected>)".
// line = 0 means the problem concerns the whole file (missing, unreadable, empty).
class ParseError : public Error {
 public:
  ParseError(std::string file, int line, const std::string& problem, const std::string& expected = "");
  const std::string& file() const { return file_; }
  int line() const { return line_; }

 private:
  std::string file_;
  int line_;
};

// Throws Error("<what>: <detail>") when cond is false. For argument/config validation.
void require(bool cond, const std::string& what);

}  // namespace s3m
