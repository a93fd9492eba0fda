// A coverage-blind mutation fuzzer for machines without a clang sanitizer build: takes a target's
// seed corpus, applies seeded random mutations (byte flips, inserted/deleted bytes, duplicated or
// dropped lines, numbers replaced by extreme values) and runs the same target function the
// libFuzzer executables run. Anything but "parsed" or s3m::Error (an escaping exception) is
// reported, and the input is written to mutate_finding_<target>_<n>.bin for tests/fuzz/regress/.
// Crashes end the process (run it under ASan when available). Prefer tools/fuzz.sh when clang is there.
//
//   build/tests/fuzz/fuzz_mutate TARGET ITERATIONS [RNG_SEED]     e.g. fuzz_mutate pipeline_config 100000
#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <random>
#include <string>
#include <vector>

#include "fuzz/targets.hpp"

namespace {
namespace fs = std::filesystem;

std::vector<std::string> seeds_of(const std::string& target) {
  std::vector<std::string> out;
  const fs::path dir = fs::path(S3M_FUZZ_DIR) / "corpus" / target;
  for (const auto& e : fs::directory_iterator(dir)) {
    std::ifstream in(e.path(), std::ios::binary);
    out.emplace_back(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
  }
  std::sort(out.begin(), out.end());
  return out;
}

void mutate(std::string& s, std::mt19937_64& rng) {
  static const char* kValues[] = {"0", "-1", "1e300", "-1e300", "nan", "inf", "4294967296", "[]", "{}", "~", "\"\"",
                                  ":", "- ", "\n", "\t", "99999999999999999999", "0.0000001", "&a", "*a", "!!binary"};
  auto pos = [&](std::size_t n) { return n == 0 ? 0 : std::uniform_int_distribution<std::size_t>(0, n - 1)(rng); };
  switch (rng() % 6) {
    case 0: if (!s.empty()) s[pos(s.size())] ^= static_cast<char>(1u << (rng() % 8)); break;
    case 1: s.insert(pos(s.size() + 1), 1, static_cast<char>(rng() % 256)); break;
    case 2: if (!s.empty()) s.erase(pos(s.size()), 1 + rng() % 8); break;
    case 3: s.insert(pos(s.size() + 1), kValues[rng() % std::size(kValues)]); break;
    case 4: {  // replace a token after ": " with an extreme value
      const std::size_t at = s.find(": ", pos(s.size() + 1));
      if (at == std::string::npos) break;
      const std::size_t end = s.find_first_of(",}\n", at + 2);
      s.replace(at + 2, (end == std::string::npos ? s.size() : end) - at - 2, kValues[rng() % std::size(kValues)]);
      break;
    }
    default: {  // duplicate or drop a line
      const std::size_t a = s.rfind('\n', pos(s.size() + 1)), b = s.find('\n', a == std::string::npos ? 0 : a + 1);
      const std::size_t from = a == std::string::npos ? 0 : a + 1, to = b == std::string::npos ? s.size() : b + 1;
      if (rng() % 2) s.insert(from, s.substr(from, to - from));
      else s.erase(from, to - from);
    }
  }
}

}  // namespace

int main(int argc, char** argv) {
  if (argc < 3) {
    std::fprintf(stderr, "usage: fuzz_mutate TARGET ITERATIONS [RNG_SEED]\n");
    return 2;
  }
  const s3m::fuzz::Target* t = s3m::fuzz::find_target(argv[1]);
  if (!t) {
    std::fprintf(stderr, "fuzz_mutate: no target '%s'\n", argv[1]);
    return 2;
  }
  const std::vector<std::string> seeds = seeds_of(t->name);
  std::mt19937_64 rng(argc > 3 ? std::stoull(argv[3]) : 1);
  const long n = std::stol(argv[2]);
  int findings = 0;
  for (long i = 0; i < n; ++i) {
    std::string input = seeds[i % seeds.size()];
    for (int k = 1 + static_cast<int>(rng() % 4); k > 0; --k) mutate(input, rng);
    try {
      t->fn(reinterpret_cast<const std::uint8_t*>(input.data()), input.size());
    } catch (const std::exception& e) {
      const std::string file = "mutate_finding_" + t->name + "_" + std::to_string(findings++) + ".bin";
      std::ofstream(file, std::ios::binary) << input;
      std::fprintf(stderr, "fuzz_mutate: input %ld: %s (saved to %s)\n", i, e.what(), file.c_str());
    }
  }
  std::printf("fuzz_mutate %s: %ld inputs from %zu seeds, %d findings\n", t->name.c_str(), n, seeds.size(), findings);
  return findings > 0 ? 1 : 0;
}
