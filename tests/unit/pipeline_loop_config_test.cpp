// The `loop_closing:` preset section and the vocabulary it names: keys load (paths relative to the
// preset), bad values are refused, and a missing or corrupt vocabulary stops with a clear error
// naming the file before any frame is processed.
#include <filesystem>
#include <fstream>
#include <functional>

#include <unistd.h>

#include <gtest/gtest.h>

#include "s3m/core/error.hpp"
#include "s3m/features/bow_vocabulary.hpp"
#include "s3m/pipeline/factories.hpp"

namespace s3m::pipeline {
namespace {
namespace fs = std::filesystem;

fs::path tmp_dir() {
  const fs::path d = fs::temp_directory_path() / ("s3m_pipeline_loop_config_" + std::to_string(::getpid()));
  fs::create_directories(d);
  return d;
}

// Removes this process's files when the tests end.
class Cleanup : public ::testing::Environment {
 public:
  void TearDown() override {
    std::error_code ec;
    fs::remove_all(tmp_dir(), ec);
  }
};
const auto* const kCleanup = ::testing::AddGlobalTestEnvironment(new Cleanup);

std::string write(const std::string& name, const std::string& text) {
  const fs::path p = tmp_dir() / name;
  std::ofstream(p, std::ios::binary) << text;
  return p.string();
}

std::string error_of(const std::function<void()>& f) {
  try {
    f();
  } catch (const Error& e) {
    return e.what();
  }
  return "";
}

TEST(LoopClosingConfig, DefaultsAreOnWithTheShippedVocabulary) {
  const LoopClosingConfig c;
  EXPECT_TRUE(c.enabled);
  EXPECT_TRUE(c.relocalisation);
  EXPECT_TRUE(c.vocabulary.empty());
  // The shipped file loads and is what an empty path means.
  EXPECT_GT(load_vocabulary(c)->num_words(), 1000U);
}

TEST(LoopClosingConfig, LoadsKeysWithVocabularyRelativeToThePreset) {
  const auto c = load_pipeline_config(write("lc.yaml", R"(
loop_closing: {enabled: false, relocalisation: true, vocabulary: vocab/my.bin, global_ba: true, min_keyframes: 20}
)"));
  EXPECT_FALSE(c.loop_closing.enabled);
  EXPECT_TRUE(c.loop_closing.relocalisation);
  EXPECT_TRUE(c.loop_closing.global_ba);
  EXPECT_EQ(c.loop_closing.min_keyframes, 20);
  EXPECT_EQ(c.loop_closing.vocabulary, (tmp_dir() / "vocab/my.bin").string());
  EXPECT_NE(error_of([] { load_pipeline_config(write("bad.yaml", "loop_closing: {min_keyframes: 0}\n")); })
                .find("loop_closing.min_keyframes"),
            std::string::npos);
  EXPECT_NE(error_of([] { load_pipeline_config(write("bad2.yaml", "loop_closing: {enable: true}\n")); }).find("enable"),
            std::string::npos);
}

TEST(LoopClosingConfig, MissingOrCorruptVocabularyIsAClearError) {
  PipelineConfig c;
  c.loop_closing.vocabulary = (tmp_dir() / "absent.bin").string();
  const std::string missing = error_of([&] { make_slam_poses(PinholeCamera{}, c); });
  EXPECT_NE(missing.find("absent.bin"), std::string::npos) << missing;
  EXPECT_NE(missing.find("does not exist"), std::string::npos) << missing;
  // A real vocabulary with one byte flipped in the middle: the checksum catches it.
  std::ifstream in(features::default_vocabulary_path(), std::ios::binary);
  std::string bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  ASSERT_GT(bytes.size(), 1000U);
  bytes[bytes.size() / 2] = static_cast<char>(bytes[bytes.size() / 2] ^ 0x5A);
  c.loop_closing.vocabulary = write("corrupt.bin", bytes);
  const std::string corrupt = error_of([&] { make_slam_poses(PinholeCamera{}, c); });
  EXPECT_NE(corrupt.find("corrupt.bin"), std::string::npos) << corrupt;
  EXPECT_NE(corrupt.find("loop_closing.vocabulary"), std::string::npos) << corrupt;
  // With both features off no vocabulary is needed at all.
  c.loop_closing.enabled = c.loop_closing.relocalisation = false;
  EXPECT_NO_THROW(make_slam_poses(PinholeCamera{}, c));
}

}  // namespace
}  // namespace s3m::pipeline
