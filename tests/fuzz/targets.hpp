#pragma once
// Fuzz targets for every file format s3m reads. Each target writes the fuzzer's bytes to a scratch
// file (the parsers take paths, like users' files) and runs the real reader on it. The contract
// under test: a reader either succeeds or throws s3m::Error; anything else (crash, sanitizer
// report, std::exception, abort, hang) is a bug. Targets therefore catch s3m::Error only.
//
// The same functions run in two places: the libFuzzer executables (S3M_FUZZ, clang) and the
// test_fuzz_corpus gtest, which replays every seed and every regression input in normal CI.
#include <cstddef>
#include <cstdint>
#include <ostream>
#include <string>
#include <string_view>
#include <vector>

namespace s3m::fuzz {

using TargetFn = void (*)(const std::uint8_t* data, std::size_t size);

struct Target {
  std::string name;  // also the corpus folder: tests/fuzz/corpus/<name>/ and tests/fuzz/regress/<name>/
  TargetFn fn;
};

// gtest prints parameters with this (the test name already says which target).
inline void PrintTo(const Target& t, std::ostream* os) { *os << t.name; }

// Every target compiled into this build (modules that are not built contribute none).
const std::vector<Target>& all_targets();
const Target* find_target(std::string_view name);

// Scratch space: one private directory per process, created on first use, removed at exit.
const std::string& scratch_dir();
// Writes bytes to <scratch>/<name> (replacing it) and returns the path.
std::string write_scratch(const std::string& name, const std::uint8_t* data, std::size_t size);
std::string write_scratch(const std::string& name, std::string_view bytes);

// Splits data on the 4-byte separator "\n--\n" into at most max_parts parts (for multi-file inputs).
std::vector<std::string_view> split_parts(const std::uint8_t* data, std::size_t size, std::size_t max_parts);

// Runs f and swallows s3m::Error (the expected outcome for bad input).
template <typename F>
void expect_clean(F&& f);

}  // namespace s3m::fuzz

#include "s3m/core/error.hpp"

template <typename F>
void s3m::fuzz::expect_clean(F&& f) {
  try {
    f();
  } catch (const s3m::Error&) {
  }
}
