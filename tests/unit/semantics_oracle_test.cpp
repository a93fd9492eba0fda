// Oracle noise statistics against their parameters, on a synthetic label image with many regions.
#include <gtest/gtest.h>

#include <map>

#include "s3m/core/error.hpp"
#include "s3m/semantics/oracle_segmenter.hpp"

using namespace s3m;
using namespace s3m::semantics;

namespace {
constexpr int kBlock = 8, kGrid = 40;  // 1600 square regions of 8x8 px
// Block (i, j) has class 1 + 3 (i mod 3) + (j mod 3): no two 8-neighbouring blocks share a class,
// so every block is its own connected region. Classes 1..9 = wall..bed.
cv::Mat grid_labels() {
  cv::Mat gt(kGrid * kBlock, kGrid * kBlock, CV_16UC1);
  for (int r = 0; r < gt.rows; ++r)
    for (int c = 0; c < gt.cols; ++c) gt.at<ClassId>(r, c) = ClassId(1 + 3 * ((r / kBlock) % 3) + (c / kBlock) % 3);
  return gt;
}
ClassId block_label(const cv::Mat& labels, int bi, int bj) {  // majority label of a block
  std::map<ClassId, int> n;
  for (int r = 0; r < kBlock; ++r)
    for (int c = 0; c < kBlock; ++c) ++n[labels.at<ClassId>(bi * kBlock + r, bj * kBlock + c)];
  return std::max_element(n.begin(), n.end(), [](auto& a, auto& b) { return a.second < b.second; })->first;
}
OracleNoiseConfig quiet() {
  OracleNoiseConfig c;
  c.enabled = true;
  c.confusion_rate = c.drop_rate = 0;
  c.boundary_flip_prob = 0;
  return c;
}
}  // namespace

TEST(SemanticsOracle, WithoutNoiseCopiesLabelsWithCertainty) {
  cv::Mat gt = grid_labels();
  gt(cv::Rect(0, 0, 4, 4)).setTo(0);  // unknown stays unknown with probability 0
  const LabelMap m = OracleSegmenter({}, 3).segment_labels(gt);
  EXPECT_EQ(cv::countNonZero(m.argmax != gt), 0);
  EXPECT_FLOAT_EQ(m.prob(10, 10, 0), 1.f);
  EXPECT_FLOAT_EQ(m.prob(10, 10, 1), 0.f);
  EXPECT_FLOAT_EQ(m.prob(0, 0, 0), 0.f);
  RgbdFrame no_labels;
  no_labels.rgb = cv::Mat(4, 4, CV_8UC3);
  OracleSegmenter oracle;
  EXPECT_THROW(oracle.segment(no_labels), Error);
  EXPECT_THROW(oracle.segment(no_labels.rgb), Error);
}

TEST(SemanticsOracle, ConfusionRateAndTargetsMatchParameters) {
  OracleNoiseConfig cfg = quiet();
  cfg.confusion_rate = 0.2;
  cfg.seed = 7;
  const cv::Mat gt = grid_labels();
  const LabelMap m = OracleSegmenter(cfg).segment_labels(gt, 3);
  const auto similar = default_similar();
  int confused = 0;
  for (int i = 0; i < kGrid; ++i)
    for (int j = 0; j < kGrid; ++j) {
      const ClassId truth = block_label(gt, i, j), got = block_label(m.argmax, i, j);
      if (got == truth) continue;
      ++confused;
      const auto& s = similar.at(truth);
      EXPECT_NE(std::find(s.begin(), s.end(), got), s.end()) << "confused to a class not similar to the truth";
      EXPECT_EQ(m.id(i * kBlock + 4, j * kBlock + 4, 1), truth) << "rank 2 of a wrong pixel is the true class";
    }
  // 1600 regions: binomial sd = 0.01; 4 sd tolerance
  EXPECT_NEAR(confused / double(kGrid * kGrid), 0.2, 0.04);
}

TEST(SemanticsOracle, DropRateMatchesAndDropsTakeANeighbourClass) {
  OracleNoiseConfig cfg = quiet();
  cfg.drop_rate = 0.15;
  cfg.seed = 11;
  const cv::Mat gt = grid_labels();
  const LabelMap m = OracleSegmenter(cfg).segment_labels(gt);
  int dropped = 0;
  for (int i = 1; i < kGrid - 1; ++i)
    for (int j = 1; j < kGrid - 1; ++j) {
      const ClassId got = block_label(m.argmax, i, j);
      if (got == block_label(gt, i, j)) continue;
      ++dropped;
      bool neighbour = false;
      for (int di = -1; di <= 1; ++di)
        for (int dj = -1; dj <= 1; ++dj) neighbour |= block_label(gt, i + di, j + dj) == got;
      EXPECT_TRUE(neighbour);
    }
  EXPECT_NEAR(dropped / double((kGrid - 2) * (kGrid - 2)), 0.15, 0.04);
}

TEST(SemanticsOracle, BoundaryFlipsMatchProbabilityInsideTheBand) {
  OracleNoiseConfig cfg = quiet();
  cfg.boundary_width_px = 2;
  cfg.boundary_flip_prob = 0.3;
  const cv::Mat gt = grid_labels();
  const LabelMap m = OracleSegmenter(cfg).segment_labels(gt);
  long band = 0, flipped = 0, outside_flipped = 0;
  for (int r = 0; r < gt.rows; ++r)
    for (int c = 0; c < gt.cols; ++c) {
      // Chebyshev distance to the nearest block edge of another class (image borders are not edges)
      const int dr = std::min(r % kBlock + (r >= kBlock ? 1 : 99), kBlock - r % kBlock + (r < gt.rows - kBlock ? 0 : 99));
      const int dc = std::min(c % kBlock + (c >= kBlock ? 1 : 99), kBlock - c % kBlock + (c < gt.cols - kBlock ? 0 : 99));
      const bool in_band = std::min(dr, dc) <= 2;
      const bool changed = m.argmax.at<ClassId>(r, c) != gt.at<ClassId>(r, c);
      if (in_band) band++, flipped += changed;
      else outside_flipped += changed;
    }
  EXPECT_EQ(outside_flipped, 0);
  EXPECT_NEAR(flipped / double(band), 0.3, 0.01);
  // band confidence is the region confidence (1 here) times (1 - flip probability)
  EXPECT_NEAR(m.prob(0, 7, 0), 0.7f, 1e-6);
  EXPECT_NEAR(m.prob(3, 3, 0), 1.0f, 1e-6);
}

TEST(SemanticsOracle, ConfidencesAreCalibratedAndSeedsAreDeterministic) {
  OracleNoiseConfig cfg;
  cfg.enabled = true;
  cfg.confusion_rate = 0.2;
  cfg.drop_rate = 0.1;
  cfg.concentration = 4;  // wide spread of confidences
  cfg.seed = 3;
  const cv::Mat gt = grid_labels();
  OracleSegmenter oracle(cfg);
  // Four frames pooled; bins of top-1 probability; accuracy per bin must match its mean confidence.
  std::vector<double> conf_sum(4, 0), correct(4, 0), count(4, 0);
  double total_conf = 0, total_correct = 0, n = 0;
  for (int f = 0; f < 4; ++f) {
    const LabelMap m = oracle.segment_labels(gt, f);
    for (int r = 0; r < gt.rows; ++r)
      for (int c = 0; c < gt.cols; ++c) {
        const double p = m.prob(r, c, 0);
        const bool ok = m.id(r, c, 0) == gt.at<ClassId>(r, c);
        const int b = p < 0.55 ? 0 : p < 0.7 ? 1 : p < 0.85 ? 2 : 3;
        conf_sum[b] += p, correct[b] += ok, count[b] += 1;
        total_conf += p, total_correct += ok, n += 1;
      }
  }
  EXPECT_NEAR(total_correct / n, total_conf / n, 0.02);
  for (int b = 0; b < 4; ++b) {
    ASSERT_GT(count[b], 2000) << "bin " << b;
    EXPECT_NEAR(correct[b] / count[b], conf_sum[b] / count[b], 0.06) << "bin " << b;
  }
  // same seed + frame -> identical; another frame index -> different noise
  const LabelMap a = oracle.segment_labels(gt, 5), b = OracleSegmenter(cfg).segment_labels(gt, 5);
  EXPECT_EQ(cv::countNonZero(a.argmax != b.argmax), 0);
  EXPECT_GT(cv::countNonZero(a.argmax != oracle.segment_labels(gt, 6).argmax), 0);
  // probabilities are non-increasing along the ranks and sum to at most 1
  for (int r = 0; r < gt.rows; r += 7)
    for (int c = 0; c < gt.cols; c += 5) {
      EXPECT_GE(a.prob(r, c, 0), a.prob(r, c, 1));
      EXPECT_GE(a.prob(r, c, 1), a.prob(r, c, 2));
      EXPECT_LE(a.prob(r, c, 0) + a.prob(r, c, 1) + a.prob(r, c, 2), 1.0f + 1e-6f);
    }
}

TEST(SemanticsOracle, ConfigValidationAndYaml) {
  OracleNoiseConfig bad;
  bad.confusion_rate = 0.5;
  bad.drop_rate = 0.3;
  EXPECT_THROW(OracleSegmenter{bad}, Error);
  const YAML::Node node = YAML::Load("enabled: true\nconfusion_rate: 0.05\nsimilar:\n  chair: [sofa]\n");
  const OracleNoiseConfig c = load_oracle_config(node, "test.yaml");
  EXPECT_TRUE(c.enabled);
  EXPECT_DOUBLE_EQ(c.confusion_rate, 0.05);
  EXPECT_EQ(c.similar.at(cls::kChair), (std::vector<ClassId>{cls::kSofa}));
  EXPECT_EQ(c.similar.at(cls::kWall), default_similar().at(cls::kWall));
  EXPECT_THROW(load_oracle_config(YAML::Load("similar:\n  chair: [spaceship]\n"), "t.yaml"), ParseError);
  EXPECT_THROW(load_oracle_config(YAML::Load("confusion: 0.1\n"), "t.yaml"), ParseError);
  EXPECT_THROW(load_oracle_config(YAML::Load("similar:\n  [chair]: [sofa]\n"), "t.yaml"), ParseError);
}
