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
  const slam::LoopClosingConfig c;
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
  EXPECT_FALSE(c.slam.loop_closing.enabled);
  EXPECT_TRUE(c.slam.loop_closing.relocalisation);
  EXPECT_TRUE(c.slam.loop_closing.loop.global_ba);
  EXPECT_EQ(c.slam.loop_closing.loop.min_keyframes, 20);
  EXPECT_EQ(c.slam.loop_closing.vocabulary, (tmp_dir() / "vocab/my.bin").string());
  EXPECT_NE(error_of([] { load_pipeline_config(write("bad.yaml", "loop_closing: {min_keyframes: 0}\n")); })
                .find("loop_closing.min_keyframes"),
            std::string::npos);
  EXPECT_NE(error_of([] { load_pipeline_config(write("bad2.yaml", "loop_closing: {enable: true}\n")); }).find("enable"),
            std::string::npos);
}

TEST(LoopClosingConfig, EveryLoopAndRelocKeyIsSettableFromAPreset) {
  const auto c = load_pipeline_config(write("lc_all.yaml", R"(
loop_closing:
  min_keyframes_since_loop: 7
  direct_level: 3
  detector: {min_common_words_ratio: 0.7, group_score_ratio: 0.6, group_neighbours: 8, consistency: 2}
  bow_match: {max_hamming: 40, ratio: 0.8}
  min_bow_matches: 25
  ransac: {max_iterations: 200, threshold_m: 0.04, depth_ratio: 0.01, min_inliers: 18, seed: 9}
  loop_group_size: 12
  search_radius_factor: 2.5
  min_projection_matches: 35
  essential_min_weight: 90
  pose_graph: {max_iterations: 20, loop_huber: 1.5}
  ba: {first_iterations: 4, second_iterations: 8, chi2_mono: 6.0, chi2_stereo: 8.0, max_local_keyframes: 15, global_iterations: 9}
  reloc:
    max_candidates: 6
    min_score_ratio: 0.7
    bow_match: {max_hamming: 45, ratio: 0.9}
    min_bow_matches: 14
    pnp: {iterations: 250, reprojection_px: 3.5, confidence: 0.98, min_inliers: 28}
    local_keyframes: 18
    wide_radius_factor: 9
    search_radius_factor: 2.5
    min_final_inliers: 32
    snapshot_keyframes: 30
)"));
  const slam::LoopConfig& l = c.slam.loop_closing.loop;
  EXPECT_EQ(l.min_keyframes_since_loop, 7);
  EXPECT_EQ(l.direct_level, 3);
  EXPECT_DOUBLE_EQ(l.detector.min_common_words_ratio, 0.7);
  EXPECT_DOUBLE_EQ(l.detector.group_score_ratio, 0.6);
  EXPECT_EQ(l.detector.group_neighbours, 8);
  EXPECT_EQ(l.detector.consistency, 2);
  EXPECT_EQ(l.bow_match.max_hamming, 40);
  EXPECT_DOUBLE_EQ(l.bow_match.ratio, 0.8);
  EXPECT_EQ(l.min_bow_matches, 25);
  EXPECT_EQ(l.ransac.max_iterations, 200);
  EXPECT_DOUBLE_EQ(l.ransac.threshold_m, 0.04);
  EXPECT_DOUBLE_EQ(l.ransac.depth_ratio, 0.01);
  EXPECT_EQ(l.ransac.min_inliers, 18);
  EXPECT_EQ(l.ransac.seed, 9U);
  EXPECT_EQ(l.loop_group_size, 12);
  EXPECT_DOUBLE_EQ(l.search_radius_factor, 2.5);
  EXPECT_EQ(l.min_projection_matches, 35);
  EXPECT_EQ(l.essential_min_weight, 90);
  EXPECT_EQ(l.pose_graph.max_iterations, 20);
  EXPECT_DOUBLE_EQ(l.pose_graph.loop_huber, 1.5);
  EXPECT_EQ(l.ba.first_iterations, 4);
  EXPECT_EQ(l.ba.second_iterations, 8);
  EXPECT_DOUBLE_EQ(l.ba.chi2_mono, 6.0);
  EXPECT_DOUBLE_EQ(l.ba.chi2_stereo, 8.0);
  EXPECT_EQ(l.ba.max_local_keyframes, 15);
  EXPECT_EQ(l.ba.global_iterations, 9);
  const slam::RelocConfig& r = c.slam.loop_closing.reloc;
  EXPECT_EQ(r.max_candidates, 6);
  EXPECT_DOUBLE_EQ(r.min_score_ratio, 0.7);
  EXPECT_EQ(r.bow_match.max_hamming, 45);
  EXPECT_DOUBLE_EQ(r.bow_match.ratio, 0.9);
  EXPECT_EQ(r.min_bow_matches, 14);
  EXPECT_EQ(r.pnp.iterations, 250);
  EXPECT_DOUBLE_EQ(r.pnp.reprojection_px, 3.5);
  EXPECT_DOUBLE_EQ(r.pnp.confidence, 0.98);
  EXPECT_EQ(r.pnp.min_inliers, 28);
  EXPECT_EQ(r.local_keyframes, 18);
  EXPECT_DOUBLE_EQ(r.wide_radius_factor, 9);
  EXPECT_DOUBLE_EQ(r.search_radius_factor, 2.5);
  EXPECT_EQ(r.min_final_inliers, 32);
  EXPECT_EQ(r.snapshot_keyframes, 30);
  // Typos and out-of-range values in the sub-sections name themselves.
  EXPECT_NE(error_of([] { load_pipeline_config(write("bad3.yaml", "loop_closing: {reloc: {pnp: {iter: 3}}}\n")); })
                .find("iter"),
            std::string::npos);
  EXPECT_NE(error_of([] { load_pipeline_config(write("bad4.yaml", "loop_closing: {reloc: {snapshot_keyframes: 0}}\n")); })
                .find("loop_closing.reloc.snapshot_keyframes"),
            std::string::npos);
}

TEST(LoopClosingConfig, MissingOrCorruptVocabularyIsAClearError) {
  PipelineConfig c;
  c.slam.loop_closing.vocabulary = (tmp_dir() / "absent.bin").string();
  const std::string missing = error_of([&] { make_slam_poses(PinholeCamera{}, c); });
  EXPECT_NE(missing.find("absent.bin"), std::string::npos) << missing;
  EXPECT_NE(missing.find("does not exist"), std::string::npos) << missing;
  // A real vocabulary with one byte flipped in the middle: the checksum catches it.
  std::ifstream in(features::default_vocabulary_path(), std::ios::binary);
  std::string bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  ASSERT_GT(bytes.size(), 1000U);
  bytes[bytes.size() / 2] = static_cast<char>(bytes[bytes.size() / 2] ^ 0x5A);
  c.slam.loop_closing.vocabulary = write("corrupt.bin", bytes);
  const std::string corrupt = error_of([&] { make_slam_poses(PinholeCamera{}, c); });
  EXPECT_NE(corrupt.find("corrupt.bin"), std::string::npos) << corrupt;
  EXPECT_NE(corrupt.find("loop_closing.vocabulary"), std::string::npos) << corrupt;
  // With both features off no vocabulary is needed at all.
  c.slam.loop_closing.enabled = c.slam.loop_closing.relocalisation = false;
  EXPECT_NO_THROW(make_slam_poses(PinholeCamera{}, c));
}

}  // namespace
}  // namespace s3m::pipeline
