// Place recognition end to end: train a vocabulary on one set of procedural places, enrol other
// places in the database, query with revisited (homography-warped) views and with unseen places.
#include <gtest/gtest.h>

#include "features_bow_test_images.hpp"
#include <opencv2/features2d.hpp>

#include "s3m/features/bow_database.hpp"
#include "s3m/features/bow_matcher.hpp"
#include "s3m/features/bow_vocabulary.hpp"

namespace s3m::features {
namespace {

constexpr int kFeatures = 400;

class PlaceRecognition : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    std::vector<cv::Mat> training;
    for (uint32_t s = 0; s < 30; ++s) training.push_back(extract_orb_descriptors(test::make_place_image(1000 + s), kFeatures));
    VocabularyConfig config;
    config.branching = 8;
    config.levels = 4;
    vocab_ = new Vocabulary(Vocabulary::train(training, config));
  }
  static void TearDownTestSuite() { delete vocab_; }
  static BowVector bow(const cv::Mat& image) { return vocab_->transform(extract_orb_descriptors(image, kFeatures)); }
  static Vocabulary* vocab_;
};
Vocabulary* PlaceRecognition::vocab_ = nullptr;

TEST_F(PlaceRecognition, RevisitedPlacesAreRecalledAtRankOneAndUnrelatedPlacesScoreLow) {
  constexpr int kPlaces = 20;
  BowDatabase db;
  std::vector<cv::Mat> places;
  for (int p = 0; p < kPlaces; ++p) {
    places.push_back(test::make_place_image(5000 + p));
    db.add(p, bow(places.back()));
  }
  int recalled = 0;
  double worst_true_score = 1.0;
  for (int p = 0; p < kPlaces; ++p) {
    const auto results = db.query(bow(test::make_revisit(places[p], 77 + p)), 3);
    ASSERT_FALSE(results.empty());
    if (results[0].entry_id == p) {
      ++recalled;
      worst_true_score = std::min(worst_true_score, results[0].score);
    }
  }
  double best_unrelated_score = 0.0;
  for (int q = 0; q < kPlaces; ++q) {
    const auto results = db.query(bow(test::make_revisit(test::make_place_image(9000 + q), 11 + q)), 1);
    if (!results.empty()) best_unrelated_score = std::max(best_unrelated_score, results[0].score);
  }
  std::printf("recall@1 %d/%d, worst true score %.3f, best unrelated score %.3f\n", recalled, kPlaces,
              worst_true_score, best_unrelated_score);
  EXPECT_GE(recalled, 19);  // recall@1 >= 95 %
  // Rejection: a single threshold separates every recalled revisit from every unrelated place.
  EXPECT_LT(best_unrelated_score, worst_true_score);
}


// The shipped vocabulary (trained on real indoor images) also recognises the procedural places.
TEST(ShippedVocabulary, LoadsAndRecallsRevisitedPlaces) {
  const Vocabulary v = Vocabulary::load(default_vocabulary_path());
  EXPECT_EQ(v.branching(), 10);
  EXPECT_EQ(v.levels(), 5);
  EXPECT_GT(v.num_words(), 10000U);
  BowDatabase db;
  std::vector<cv::Mat> places;
  for (int p = 0; p < 10; ++p) {
    places.push_back(test::make_place_image(7000 + p));
    db.add(p, v.transform(extract_orb_descriptors(places.back(), kFeatures)));
  }
  int recalled = 0;
  for (int p = 0; p < 10; ++p) {
    const auto r = db.query(v.transform(extract_orb_descriptors(test::make_revisit(places[p], 300 + p), kFeatures)), 1);
    recalled += !r.empty() && r[0].entry_id == p;
  }
  EXPECT_GE(recalled, 9);
}

// BoW-accelerated matching between a place and its revisit: matches must agree with the known
// homography (the reprojected keypoint lands within a few pixels).
TEST_F(PlaceRecognition, BowMatchesAgreeWithTheKnownHomography) {
  const cv::Mat place = test::make_place_image(5003);
  cv::Mat H;
  const cv::Mat view = test::make_revisit(place, 80, 12.0, &H);
  auto orb = cv::ORB::create(kFeatures, 1.2F, 8);
  std::vector<cv::KeyPoint> kp_a, kp_b;
  cv::Mat d_a, d_b;
  orb->detectAndCompute(place, cv::noArray(), kp_a, d_a);
  orb->detectAndCompute(view, cv::noArray(), kp_b, d_b);
  FeatureVector fv_a, fv_b;
  vocab_->transform(d_a, &fv_a, 2);
  vocab_->transform(d_b, &fv_b, 2);
  const auto matches = match_by_bow(fv_a, d_a, fv_b, d_b);
  int correct = 0;
  std::set<int> used_a;
  for (const auto& [i, j] : matches) {
    EXPECT_TRUE(used_a.insert(i).second);  // one-to-one
    std::vector<cv::Point2f> src{kp_a[size_t(i)].pt}, dst;
    cv::perspectiveTransform(src, dst, H);
    correct += cv::norm(dst[0] - kp_b[size_t(j)].pt) < 4.0;
  }
  std::printf("%zu BoW matches, %d consistent with H\n", matches.size(), correct);
  EXPECT_GE(matches.size(), 60U);
  EXPECT_GE(correct, int(0.9 * double(matches.size())));
}

}  // namespace
}  // namespace s3m::features
