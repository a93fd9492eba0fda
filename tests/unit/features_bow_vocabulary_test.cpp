// Vocabulary mechanics: scores on hand-made vectors, k-medians on separable clusters, IDF,
// determinism, the inverted index against brute force, and the file format's error handling.
#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <random>

#include "features_bow_test_images.hpp"
#include "s3m/core/error.hpp"
#include "s3m/features/bow_database.hpp"
#include "s3m/features/bow_vocabulary.hpp"

namespace s3m::features {
namespace {

// One descriptor matrix whose rows are noisy copies (flip `noise_bits`) of the given prototypes.
cv::Mat noisy_copies(const std::vector<Descriptor256>& prototypes, int copies, int noise_bits, std::mt19937& rng) {
  cv::Mat d(int(prototypes.size()) * copies, 32, CV_8UC1);
  std::uniform_int_distribution<int> bit(0, 255);
  int row = 0;
  for (const auto& p : prototypes) {
    for (int c = 0; c < copies; ++c, ++row) {
      Descriptor256 x = p;
      for (int b = 0; b < noise_bits; ++b) {
        const int i = bit(rng);
        x[i / 64] ^= uint64_t{1} << (i % 64);
      }
      std::memcpy(d.ptr<uint8_t>(row), x.data(), 32);
    }
  }
  return d;
}

std::vector<Descriptor256> random_prototypes(int n, std::mt19937& rng) {
  std::uniform_int_distribution<uint64_t> u;
  std::vector<Descriptor256> p(n);
  for (auto& d : p) d = {u(rng), u(rng), u(rng), u(rng)};
  return p;
}

TEST(BowVector, L1ScoreMatchesHandComputation) {
  // a = {1: 0.5, 2: 0.5}, b = {2: 0.25, 3: 0.75}: 1 - 0.5 * (0.5 + 0.25 + 0.75) = 0.25 = min(0.5, 0.25).
  BowVector a{{1, 0.5}, {2, 0.5}}, b{{2, 0.25}, {3, 0.75}};
  EXPECT_DOUBLE_EQ(l1_score(a, b), 0.25);
  EXPECT_DOUBLE_EQ(l1_score(a, a), 1.0);
  EXPECT_DOUBLE_EQ(l1_score(a, BowVector{{7, 1.0}}), 0.0);
  BowVector c{{4, 2.0}, {5, 6.0}};
  normalize_l1(c);
  EXPECT_DOUBLE_EQ(c[4], 0.25);
  EXPECT_DOUBLE_EQ(c[5], 0.75);
}

TEST(BowVector, HammingCountsDifferingBits) {
  Descriptor256 a{0, 0, 0, 0}, b{0b1011, 0, uint64_t{1} << 63, ~uint64_t{0}};
  EXPECT_EQ(hamming(a, b), 3 + 1 + 64);
  cv::Mat bad(1, 16, CV_8UC1);
  EXPECT_THROW(descriptor_from_row(bad, 0), Error);
}

TEST(Vocabulary, SeparableClustersBecomeDistinctWordsAndCopiesShareThem) {
  std::mt19937 rng(3);
  const auto prototypes = random_prototypes(8, rng);
  // Two "images" each containing all 8 clusters: every word is in every image, so IDF = log(2/2) = 0,
  // except when a third image holds just one cluster.
  std::vector<cv::Mat> images{noisy_copies(prototypes, 20, 6, rng), noisy_copies(prototypes, 20, 6, rng),
                              noisy_copies({prototypes[0]}, 20, 6, rng)};
  VocabularyConfig config;
  config.branching = 8;
  config.levels = 1;
  const Vocabulary v = Vocabulary::train(images, config);
  ASSERT_EQ(v.num_words(), 8U);
  EXPECT_EQ(v.training_images(), 3U);
  std::set<WordId> words;
  for (const auto& p : prototypes) words.insert(v.word_of(p));
  EXPECT_EQ(words.size(), 8U);  // k-means++ seeding finds all 8 well-separated clusters
  // Word of prototype 0 is in all 3 images (weight 0); the others in 2 of 3 (log 1.5).
  EXPECT_NEAR(v.word_weight(v.word_of(prototypes[0])), 0.0, 1e-6);
  EXPECT_NEAR(v.word_weight(v.word_of(prototypes[1])), std::log(1.5), 1e-6);
  // A noisy copy lands in its prototype's word.
  const cv::Mat probe = noisy_copies({prototypes[5]}, 1, 10, rng);
  EXPECT_EQ(v.word_of(descriptor_from_row(probe, 0)), v.word_of(prototypes[5]));
}

TEST(Vocabulary, TrainingIsDeterministicAndSaveLoadRoundTrips) {
  std::vector<cv::Mat> images;
  for (uint32_t s = 0; s < 6; ++s) images.push_back(extract_orb_descriptors(test::make_place_image(s), 300));
  VocabularyConfig config;
  config.branching = 5;
  config.levels = 3;
  const Vocabulary a = Vocabulary::train(images, config);
  const Vocabulary b = Vocabulary::train(images, config);
  const auto dir = std::filesystem::temp_directory_path() / ("s3m_vocab_test_" + std::to_string(::getpid()));
  std::filesystem::remove_all(dir);
  std::filesystem::create_directories(dir);
  a.save((dir / "a.bin").string());
  b.save((dir / "b.bin").string());
  auto bytes = [](const std::filesystem::path& p) {
    std::ifstream in(p, std::ios::binary);
    return std::string(std::istreambuf_iterator<char>(in), {});
  };
  EXPECT_EQ(bytes(dir / "a.bin"), bytes(dir / "b.bin"));
  std::size_t files = 0;  // a.bin and b.bin only: no temporary file left behind
  for (const auto& e : std::filesystem::directory_iterator(dir)) files += (void(e), 1);
  EXPECT_EQ(files, 2u);

  const Vocabulary loaded = Vocabulary::load((dir / "a.bin").string());
  EXPECT_EQ(loaded.num_words(), a.num_words());
  EXPECT_EQ(loaded.num_nodes(), a.num_nodes());
  EXPECT_EQ(loaded.branching(), 5);
  EXPECT_EQ(loaded.levels(), 3);
  const cv::Mat query = extract_orb_descriptors(test::make_place_image(42), 300);
  FeatureVector fa, fl;
  EXPECT_EQ(a.transform(query, &fa, 1), loaded.transform(query, &fl, 1));
  EXPECT_EQ(fa, fl);
  size_t indexed = 0;
  for (const auto& [node, features] : fa) indexed += features.size();
  EXPECT_EQ(indexed, size_t(query.rows));  // the direct index covers every feature once
  EXPECT_LE(fa.size(), 5U);                // level 1 has at most k nodes
  std::filesystem::remove_all(dir);
}

TEST(Vocabulary, CorruptFilesAreRejectedWithTheProblemNamed) {
  std::mt19937 rng(9);
  VocabularyConfig config;
  config.branching = 4;
  config.levels = 2;
  const Vocabulary v = Vocabulary::train({noisy_copies(random_prototypes(16, rng), 5, 4, rng)}, config);
  const auto dir = std::filesystem::temp_directory_path() / "s3m_vocab_corrupt";
  std::filesystem::create_directories(dir);
  const std::string good = (dir / "good.bin").string();
  v.save(good);
  std::ifstream in(good, std::ios::binary);
  const std::string bytes(std::istreambuf_iterator<char>(in), {});
  auto expect_error = [&](const std::string& content, const std::string& fragment) {
    const std::string path = (dir / "bad.bin").string();
    std::ofstream(path, std::ios::binary) << content;
    try {
      Vocabulary::load(path);
      ADD_FAILURE() << "no error for " << fragment;
    } catch (const ParseError& e) {
      EXPECT_NE(std::string(e.what()).find(fragment), std::string::npos) << e.what();
      EXPECT_EQ(e.file(), path);
    }
  };
  expect_error("hello world", "bad magic");
  expect_error(bytes.substr(0, bytes.size() - 20), "truncated");
  std::string flipped = bytes;
  flipped[bytes.size() / 2] ^= 0x10;
  expect_error(flipped, "checksum");
  std::string version = bytes;
  version[8] = 7;
  expect_error(version, "unsupported vocabulary version 7");
  EXPECT_THROW(Vocabulary::load((dir / "missing.bin").string()), ParseError);
  std::filesystem::remove_all(dir);
}

TEST(BowDatabase, QueryScoresEqualBruteForceL1AndRespectFilterAndErase) {
  std::mt19937 rng(5);
  std::uniform_int_distribution<WordId> word(0, 60);
  std::uniform_real_distribution<double> weight(0.1, 1.0);
  BowDatabase db;
  std::vector<BowVector> entries(25);
  for (int i = 0; i < 25; ++i) {
    for (int k = 0; k < 12; ++k) entries[i][word(rng)] = weight(rng);
    normalize_l1(entries[i]);
    db.add(i, entries[i]);
  }
  BowVector q;
  for (int k = 0; k < 12; ++k) q[word(rng)] = weight(rng);
  normalize_l1(q);
  const auto results = db.query(q);
  ASSERT_FALSE(results.empty());
  for (size_t i = 0; i < results.size(); ++i) {
    EXPECT_NEAR(results[i].score, l1_score(q, entries[results[i].entry_id]), 1e-12);
    if (i > 0) {
      EXPECT_GE(results[i - 1].score, results[i].score);
    }
  }
  const int best = results[0].entry_id;
  const auto filtered = db.query(q, 3, [&](int id) { return id != best; });
  EXPECT_LE(filtered.size(), 3U);
  for (const auto& r : filtered) EXPECT_NE(r.entry_id, best);
  db.erase(best);
  EXPECT_EQ(db.size(), 24U);
  for (const auto& r : db.query(q)) EXPECT_NE(r.entry_id, best);
}

TEST(VocabularyConfig, RejectsBadValues) {
  VocabularyConfig c;
  c.branching = 1;
  EXPECT_THROW(c.validate(), Error);
  c = {};
  c.levels = 0;
  EXPECT_THROW(c.validate(), Error);
  EXPECT_THROW(Vocabulary::train({}, VocabularyConfig{}), Error);
}

}  // namespace
}  // namespace s3m::features
