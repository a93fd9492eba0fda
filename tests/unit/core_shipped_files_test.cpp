// Where the library finds its shipped files (s3m/core/shipped_files.hpp).
#include <cstdlib>
#include <filesystem>
#include <optional>
#include <string>

#include <gtest/gtest.h>

#include "s3m/core/shipped_files.hpp"

namespace fs = std::filesystem;

namespace {
// Sets (or, with nullopt, removes) S3M_DATA_DIR for one scope, then puts back what was there.
class DataDirEnv {
 public:
  explicit DataDirEnv(const std::optional<std::string>& value) {
    if (const char* old = std::getenv("S3M_DATA_DIR")) old_ = old;
    if (value) setenv("S3M_DATA_DIR", value->c_str(), 1);
    else unsetenv("S3M_DATA_DIR");
  }
  ~DataDirEnv() {
    if (old_) setenv("S3M_DATA_DIR", old_->c_str(), 1);
    else unsetenv("S3M_DATA_DIR");
  }

 private:
  std::optional<std::string> old_;
};
}  // namespace

TEST(ShippedFiles, TheBuildsOwnTreeHasTheShippedVocabulary) {
  DataDirEnv env(std::nullopt);
  const fs::path vocab = s3m::shipped_file("vocab/orb_k10_l5.bin");
  EXPECT_TRUE(fs::is_regular_file(vocab)) << vocab;
  EXPECT_EQ(vocab.filename(), "orb_k10_l5.bin");
  EXPECT_EQ(vocab.parent_path().filename(), "vocab");
}

TEST(ShippedFiles, AMissingFileIsNamedWhereTheSourceTreeWouldHaveIt) {
  DataDirEnv env(std::nullopt);
  const fs::path root = fs::path(s3m::shipped_file("vocab/orb_k10_l5.bin")).parent_path().parent_path();
  EXPECT_EQ(fs::path(s3m::shipped_file("models/no_such_model.yaml")), root / "models" / "no_such_model.yaml");
}

TEST(ShippedFiles, TheEnvironmentWinsEvenWithoutTheFile) {
  DataDirEnv env(std::string("/nonexistent/s3m_share"));
  EXPECT_EQ(s3m::shipped_file("vocab/orb_k10_l5.bin"), "/nonexistent/s3m_share/vocab/orb_k10_l5.bin");
}

TEST(ShippedFiles, AnEmptyEnvironmentValueIsIgnored) {
  std::string unset_result;
  {
    DataDirEnv env(std::nullopt);
    unset_result = s3m::shipped_file("config/sim.yaml");
  }
  DataDirEnv env(std::string(""));
  EXPECT_EQ(s3m::shipped_file("config/sim.yaml"), unset_result);
}
