#pragma once
// Line-oriented text parsing shared by the io readers: whitespace/comma separated tokens,
// '#' comments, and number parsing that rejects garbage, NaN and Inf with file:line context.
#include <fstream>
#include <string>
#include <string_view>
#include <vector>

namespace s3m::io {

class LineReader {
 public:
  // Throws ParseError(path, 0, "file not found" / "cannot open") when the file is unusable.
  // what names the expected content for the message ("a TUM trajectory", ...).
  LineReader(const std::string& path, const std::string& what);

  // Advances to the next non-empty, non-comment line and splits it on spaces, tabs and commas
  // (TUM's associate.py accepts all three). Returns false at end of file.
  bool next(std::vector<std::string_view>& tokens);
  int line() const { return line_no_; }
  const std::string& path() const { return path_; }

  // Throws ParseError at the current line.
  [[noreturn]] void fail(const std::string& problem, const std::string& expected = "") const;
  // A finite double from token i (name used in the message), else ParseError.
  double number(const std::vector<std::string_view>& tokens, std::size_t i, const std::string& name) const;
  // A coordinate in metres from token i: finite and |x| <= kMaxCoordinateM, else ParseError.
  double coordinate_m(const std::vector<std::string_view>& tokens, std::size_t i, const std::string& name) const;
  // Requires exactly n tokens (or at least n when at_least) naming the expected layout.
  void expect_tokens(const std::vector<std::string_view>& tokens, std::size_t n, const std::string& layout,
                     bool at_least = false) const;

 private:
  std::string path_;
  std::ifstream in_;
  std::string buffer_;
  int line_no_ = 0;
};

// Largest accepted coordinate magnitude [m]. Far beyond any real scene (a million km), yet small
// enough that squared errors and sums stay finite in double and coordinates fit in float.
inline constexpr double kMaxCoordinateM = 1e9;

// Parses a whole token as a finite double; false on garbage, trailing characters, NaN or Inf.
bool parse_finite_double(std::string_view token, double& out);
// True for a token that reads as inf or nan ("inf", "-inf", "nan", "NaN", "1e999", ...), which
// parse_finite_double() refuses like garbage; files that mark missing values that way need to tell.
bool is_non_finite_number(std::string_view token);

}  // namespace s3m::io
