#include "s3m/io/text_lines.hpp"

#include <charconv>
#include <cmath>

#include <fmt/format.h>

#include "s3m/core/error.hpp"
#include "s3m/core/input_file.hpp"

namespace s3m::io {

LineReader::LineReader(const std::string& path, const std::string& what) : path_(path) {
  in_ = open_input_file(path, what);
}

bool LineReader::next(std::vector<std::string_view>& tokens) {
  tokens.clear();
  while (std::getline(in_, buffer_)) {
    ++line_no_;
    std::string_view line(buffer_);
    if (const auto hash = line.find('#'); hash != std::string_view::npos) line = line.substr(0, hash);
    std::size_t pos = 0;
    while (pos < line.size()) {
      const auto is_sep = [](char c) { return c == ' ' || c == '\t' || c == ',' || c == '\r'; };
      while (pos < line.size() && is_sep(line[pos])) ++pos;
      std::size_t end = pos;
      while (end < line.size() && !is_sep(line[end])) ++end;
      if (end > pos) tokens.push_back(line.substr(pos, end - pos));
      pos = end;
    }
    if (!tokens.empty()) return true;
  }
  if (in_.bad()) throw ParseError(path_, line_no_, "read error");
  return false;
}

void LineReader::fail(const std::string& problem, const std::string& expected) const {
  throw ParseError(path_, line_no_, problem, expected);
}

bool parse_finite_double(std::string_view token, double& out) {
  if (!token.empty() && token.front() == '+') token.remove_prefix(1);
  const char* end = token.data() + token.size();
  const auto [ptr, ec] = std::from_chars(token.data(), end, out);
  return ec == std::errc() && ptr == end && std::isfinite(out);
}

bool is_non_finite_number(std::string_view token) {
  const std::string tok(token);
  return !std::isfinite(std::strtod(tok.c_str(), nullptr)) && tok.find_first_of("nNiI") != std::string::npos;
}

double LineReader::number(const std::vector<std::string_view>& tokens, std::size_t i,
                          const std::string& name) const {
  double v = 0;
  if (parse_finite_double(tokens.at(i), v)) return v;
  // Distinguish NaN/Inf from garbage: both are errors, but the message should say which.
  const std::string tok(tokens[i]);
  fail((is_non_finite_number(tok) ? "non-finite value '" : "cannot parse '") + tok + "' as " + name,
       "a finite number in column " + std::to_string(i + 1));
}

double LineReader::coordinate_m(const std::vector<std::string_view>& tokens, std::size_t i,
                                const std::string& name) const {
  const double v = number(tokens, i, name);
  if (std::abs(v) > kMaxCoordinateM)
    fail(fmt::format("coordinate {} = {} m is implausibly large", name, tokens[i]),
         fmt::format("|{}| <= 1e9 m in column {}", name, i + 1));
  return v;
}

void LineReader::expect_tokens(const std::vector<std::string_view>& tokens, std::size_t n,
                               const std::string& layout, bool at_least) const {
  if (tokens.size() == n || (at_least && tokens.size() > n)) return;
  fail("found " + std::to_string(tokens.size()) + " columns",
       (at_least ? "at least " : "") + std::to_string(n) + " columns '" + layout + "'");
}

}  // namespace s3m::io
