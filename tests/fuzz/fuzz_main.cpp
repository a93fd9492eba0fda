// libFuzzer entry point; S3M_FUZZ_TARGET (a string literal, set per executable by CMake) picks the target.
#include <cstdio>
#include <cstdlib>

#include "fuzz/targets.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  static const s3m::fuzz::Target* target = [] {
    const auto* t = s3m::fuzz::find_target(S3M_FUZZ_TARGET);
    if (t == nullptr) {
      std::fprintf(stderr, "s3m fuzz: unknown target '%s'\n", S3M_FUZZ_TARGET);
      std::abort();
    }
    return t;
  }();
  target->fn(data, size);
  return 0;
}
