// Replays every fuzz seed (tests/fuzz/corpus/<target>/) and every input that once crashed a reader
// (tests/fuzz/regress/<target>/) through the fuzz targets, so the whole corpus is a regression
// suite in every build (Release, and ASan+UBSan in scripts/test.sh) without needing clang.
#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <iterator>

#include "fuzz/targets.hpp"

namespace fs = std::filesystem;

namespace {

std::vector<fs::path> inputs_of(const std::string& kind, const std::string& target) {
  std::vector<fs::path> files;
  const fs::path dir = fs::path(S3M_FUZZ_DIR) / kind / target;
  if (!fs::is_directory(dir)) return files;
  for (const auto& e : fs::directory_iterator(dir))
    if (e.is_regular_file()) files.push_back(e.path());
  std::sort(files.begin(), files.end());
  return files;
}

std::string slurp(const fs::path& p) {
  std::ifstream in(p, std::ios::binary);
  return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

class FuzzCorpus : public ::testing::TestWithParam<s3m::fuzz::Target> {};

TEST_P(FuzzCorpus, EveryInputParsesOrThrowsS3mError) {
  const auto& target = GetParam();
  const auto seeds = inputs_of("corpus", target.name);
  EXPECT_GE(seeds.size(), 2u) << "each target ships a seed corpus in tests/fuzz/corpus/" << target.name;
  auto all = seeds;
  const auto regress = inputs_of("regress", target.name);
  all.insert(all.end(), regress.begin(), regress.end());
  for (const auto& file : all) {
    const std::string bytes = slurp(file);
    // Non-s3m exceptions escape the target and fail here, naming the input.
    EXPECT_NO_THROW(target.fn(reinterpret_cast<const std::uint8_t*>(bytes.data()), bytes.size())) << file;
  }
}

INSTANTIATE_TEST_SUITE_P(AllTargets, FuzzCorpus, ::testing::ValuesIn(s3m::fuzz::all_targets()),
                         [](const auto& info) { return info.param.name; });

}  // namespace
