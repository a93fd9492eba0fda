// Label fusion policies on hand-computed cases, edge cases and a fixed-seed convergence property.
#include <random>

#include <gtest/gtest.h>

#include "s3m/core/error.hpp"
#include "s3m/mapping/fusion.hpp"

using namespace s3m;
using namespace s3m::mapping;

namespace {
LabelSet L(std::initializer_list<std::pair<ClassId, float>> items) {
  LabelSet s;
  for (auto [id, p] : items) s.push(id, p);
  return s;
}
FusionConfig cfg(FusionPolicy policy, double alpha = 0.5, int k = 3) {
  FusionConfig c;
  c.policy = policy;
  c.alpha = alpha;
  c.k = k;
  return c;
}
constexpr ClassId A = 6, B = 7, C = 8, D = 9;
}  // namespace

TEST(MappingFusionPaper, EqualLabelListsKeepQ1) {
  LabelSet map = L({{A, 0.6f}, {B, 0.3f}});
  fuse_paper(map, L({{A, 0.9f}, {B, 0.05f}}), cfg(FusionPolicy::kPaper));
  EXPECT_EQ(map, L({{A, 0.6f}, {B, 0.3f}}));  // Algorithm 1 line 2: unchanged
}

TEST(MappingFusionPaper, DisjointLabelsWithAlpha) {
  // Q1 = {A .6, B .3} (p1bar .1), Q2 = {C .5, D .3} (p2bar .2), alpha .5.
  // Q2 += A:.5*.2=.1 (p2bar .1), B:.5*.1=.05.  Q1 += C:.5*.1=.05 (p1bar .05), D:.5*.05=.025.
  // products: A .06, B .015, C .025, D .0075; sum .1075.
  LabelSet map = L({{A, 0.6f}, {B, 0.3f}});
  fuse_paper(map, L({{C, 0.5f}, {D, 0.3f}}), cfg(FusionPolicy::kPaper, 0.5, 4));
  ASSERT_EQ(map.n, 4);
  EXPECT_EQ(map.ids[0], A);
  EXPECT_NEAR(map.probs[0], 0.06 / 0.1075, 1e-6);
  EXPECT_EQ(map.ids[1], C);
  EXPECT_NEAR(map.probs[1], 0.025 / 0.1075, 1e-6);
  EXPECT_EQ(map.ids[2], B);
  EXPECT_NEAR(map.probs[2], 0.015 / 0.1075, 1e-6);
  EXPECT_EQ(map.ids[3], D);
  EXPECT_NEAR(map.probs[3], 0.0075 / 0.1075, 1e-6);
}

TEST(MappingFusionPaper, DisjointTruncatesToK) {
  LabelSet map = L({{A, 0.6f}, {B, 0.3f}});
  fuse_paper(map, L({{C, 0.5f}, {D, 0.3f}}), cfg(FusionPolicy::kPaper, 0.5, 2));
  ASSERT_EQ(map.n, 2);
  EXPECT_EQ(map.ids[0], A);
  EXPECT_EQ(map.ids[1], C);
  EXPECT_NEAR(map.sum(), (0.06 + 0.025) / 0.1075, 1e-6);  // dropped mass becomes p-bar
}

TEST(MappingFusionPaper, PartialOverlap) {
  // Q1 = {A .6, B .3}, Q2 = {A .5, C .4}; alpha .5.
  // Q2 += B: .5*.1 = .05. Q1 += C: .5*.1 = .05. products A .30, B .015, C .02; sum .335.
  LabelSet map = L({{A, 0.6f}, {B, 0.3f}});
  fuse_paper(map, L({{A, 0.5f}, {C, 0.4f}}), cfg(FusionPolicy::kPaper));
  ASSERT_EQ(map.n, 3);
  EXPECT_EQ(map.ids[0], A);
  EXPECT_NEAR(map.probs[0], 0.30 / 0.335, 1e-6);
  EXPECT_EQ(map.ids[1], C);
  EXPECT_NEAR(map.probs[1], 0.02 / 0.335, 1e-6);
  EXPECT_EQ(map.ids[2], B);
  EXPECT_NEAR(map.probs[2], 0.015 / 0.335, 1e-6);
}

TEST(MappingFusionPaper, AlphaChangesTheTradeOff) {
  // Same as PartialOverlap with alpha 1: pushes are 1*.1 -> products A .30, B .03, C .04; sum .37.
  LabelSet map = L({{A, 0.6f}, {B, 0.3f}});
  fuse_paper(map, L({{A, 0.5f}, {C, 0.4f}}), cfg(FusionPolicy::kPaper, 1.0));
  EXPECT_NEAR(map.prob_of(A), 0.30 / 0.37, 1e-6);
  EXPECT_NEAR(map.prob_of(B), 0.03 / 0.37, 1e-6);
  EXPECT_NEAR(map.prob_of(C), 0.04 / 0.37, 1e-6);
}

TEST(MappingFusionPaper, ZeroUnexplainedMassUsesFloor) {
  // Both lists sum to 1 (p-bar = 0). The paper would push 0 and, with disjoint labels, divide
  // 0 by 0. With the floor eps = min_other = .001 and alpha .5:
  // Q2 = {C 1} += A: .5*.001 = .0005. Q1 = {A 1} += C: .0005. products A .0005, C .0005 -> tie.
  LabelSet map = L({{A, 1.0f}});
  fuse_paper(map, L({{C, 1.0f}}), cfg(FusionPolicy::kPaper));
  ASSERT_EQ(map.n, 2);
  EXPECT_EQ(map.ids[0], A);  // tie broken by the lower class id
  EXPECT_FLOAT_EQ(map.probs[0], 0.5f);
  EXPECT_FLOAT_EQ(map.probs[1], 0.5f);
  // Overlapping full lists: Q1 {A .7, B .3}, Q2 {A .4, C .6}; pushes .0005 each.
  // products A .28, B .00015, C .0003; sum .28045.
  map = L({{A, 0.7f}, {B, 0.3f}});
  fuse_paper(map, L({{A, 0.4f}, {C, 0.6f}}), cfg(FusionPolicy::kPaper));
  EXPECT_NEAR(map.prob_of(A), 0.28 / 0.28045, 1e-6);
  EXPECT_NEAR(map.prob_of(C), 0.0003 / 0.28045, 1e-6);
  EXPECT_NEAR(map.prob_of(B), 0.00015 / 0.28045, 1e-6);
}

TEST(MappingFusionPaper, EmptySidesAndZeroProducts) {
  LabelSet map;
  fuse_paper(map, L({{B, 0.2f}, {A, 0.7f}}), cfg(FusionPolicy::kPaper));
  EXPECT_EQ(map, L({{A, 0.7f}, {B, 0.2f}}));  // empty map takes the sorted observation
  fuse_paper(map, LabelSet{}, cfg(FusionPolicy::kPaper));
  EXPECT_EQ(map, L({{A, 0.7f}, {B, 0.2f}}));  // empty observation is a no-op
  LabelSet zero = L({{A, 0.0f}, {B, 0.0f}});
  LabelSet before = map;
  fuse_paper(map, L({{B, 0.0f}, {A, 0.0f}}), cfg(FusionPolicy::kPaper));
  EXPECT_EQ(map, before);  // all products 0: no information, unchanged
  (void)zero;
}

TEST(MappingFusionPaper, DifferentLengths) {
  // Q1 = {A .5} (p1bar .5), Q2 = {B .4, A .3, C .2} (p2bar .1), alpha .5.
  // Q2 has A. Q1 += B: .25 (p1bar .25), C: .125. products A .15, B .1, C .025; sum .275.
  LabelSet map = L({{A, 0.5f}});
  fuse_paper(map, L({{B, 0.4f}, {A, 0.3f}, {C, 0.2f}}), cfg(FusionPolicy::kPaper));
  EXPECT_NEAR(map.prob_of(A), 0.15 / 0.275, 1e-6);
  EXPECT_NEAR(map.prob_of(B), 0.10 / 0.275, 1e-6);
  EXPECT_NEAR(map.prob_of(C), 0.025 / 0.275, 1e-6);
}

TEST(MappingFusionMax, KeepsMostConfidentViewAndDecaysOnDisagreement) {
  const auto c = cfg(FusionPolicy::kMaxConfidence);
  LabelSet map = L({{A, 0.6f}, {B, 0.3f}});
  fuse_max_confidence(map, L({{A, 0.5f}, {C, 0.4f}}), c);  // weaker, agrees: unchanged
  EXPECT_EQ(map, L({{A, 0.6f}, {B, 0.3f}}));
  fuse_max_confidence(map, L({{A, 0.8f}, {C, 0.1f}}), c);  // more confident: replaces
  EXPECT_EQ(map, L({{A, 0.8f}, {C, 0.1f}}));
  fuse_max_confidence(map, L({{C, 0.5f}}), c);  // weaker, disagrees: decay by .9
  EXPECT_NEAR(map.prob_of(A), 0.72, 1e-6);
  EXPECT_NEAR(map.prob_of(C), 0.09, 1e-6);
  EXPECT_EQ(map.top(), A);
  fuse_max_confidence(map, L({{C, 0.75f}, {A, 0.05f}}), c);  // beats the decayed .72
  EXPECT_EQ(map, L({{C, 0.75f}, {A, 0.05f}}));
}

TEST(MappingFusionBayes, MultiplyAndNormaliseWithOtherBin) {
  // C = 4 classes {A,B,C,D}. Q1 = {A .6, B .2} other .2 -> u1 = .2/2 = .1 per unlisted class.
  // Q2 = {A .5, C .3} other .2 -> u2 = .1. A .3, B .2*.1=.02, C .1*.3=.03, D(other) .1*.1=.01.
  // sum .36.
  FusionConfig c = cfg(FusionPolicy::kBayesian);
  c.num_classes = 4;
  LabelSet map = L({{A, 0.6f}, {B, 0.2f}});
  fuse_bayesian(map, L({{A, 0.5f}, {C, 0.3f}}), c);
  ASSERT_EQ(map.n, 3);
  EXPECT_EQ(map.ids[0], A);
  EXPECT_NEAR(map.probs[0], 0.30 / 0.36, 1e-6);
  EXPECT_EQ(map.ids[1], C);
  EXPECT_NEAR(map.probs[1], 0.03 / 0.36, 1e-6);
  EXPECT_EQ(map.ids[2], B);
  EXPECT_NEAR(map.probs[2], 0.02 / 0.36, 1e-6);
  EXPECT_NEAR(1.0 - map.sum(), 0.01 / 0.36, 1e-6);  // the "other" bin
}

TEST(MappingFusionBayes, AgreementReinforces) {
  FusionConfig c = cfg(FusionPolicy::kBayesian);
  c.num_classes = 4;
  // Q1 = Q2 = {A .5, B .3}; u = .2/2 = .1. A .25, B .09, C .01, D .01; sum .36.
  LabelSet map = L({{A, 0.5f}, {B, 0.3f}});
  fuse_bayesian(map, L({{A, 0.5f}, {B, 0.3f}}), c);
  EXPECT_NEAR(map.prob_of(A), 0.25 / 0.36, 1e-6);
  EXPECT_NEAR(map.prob_of(B), 0.09 / 0.36, 1e-6);
}

TEST(MappingFusionConfig, ValidateAndParse) {
  FusionConfig c;
  EXPECT_NO_THROW(c.validate());
  c.k = kMaxLabels + 1;
  EXPECT_THROW(c.validate(), Error);
  c = FusionConfig{};
  c.alpha = 0.0;
  EXPECT_THROW(c.validate(), Error);
  EXPECT_EQ(parse_fusion_policy("bayesian"), FusionPolicy::kBayesian);
  EXPECT_THROW(parse_fusion_policy("median"), Error);
  const auto y = YAML::Load("policy: max_confidence\nk: 2\nalpha: 0.25\n");
  const auto parsed = fusion_config_from_yaml(y, "test.yaml");
  EXPECT_EQ(parsed.policy, FusionPolicy::kMaxConfidence);
  EXPECT_EQ(parsed.k, 2);
  EXPECT_DOUBLE_EQ(parsed.alpha, 0.25);
  EXPECT_THROW(fusion_config_from_yaml(YAML::Load("alpah: 0.3"), "test.yaml"), ParseError);
}

// Property: a voxel whose segmentation is noisy (softmax of true-class logit + noise, top-3 kept)
// converges to the true class under every policy, for several seeds.
// Max-confidence is not a consistent estimator: it follows the most confident recent view, so it
// is only required to converge when the true class also wins most per-view argmaxes.
struct ConvergenceCase {
  FusionPolicy policy;
  double signal;  // logit advantage of the true class
  int max_correct_views;  // upper bound on views whose argmax is right (noise really matters)
};
class MappingFusionConvergence : public ::testing::TestWithParam<ConvergenceCase> {};

TEST_P(MappingFusionConvergence, NoisyObservationsConvergeToTrueClass) {
  constexpr int kClasses = 8;
  for (unsigned seed : {1u, 2u, 3u, 4u, 5u}) {
    std::mt19937 rng(seed);
    std::normal_distribution<double> noise(0.0, 1.0);
    FusionConfig c = cfg(GetParam().policy);
    c.num_classes = kClasses;
    LabelSet map;
    const ClassId truth = 3;
    int correct_obs = 0;
    for (int it = 0; it < 200; ++it) {
      // Logits: truth gets +0.8 on average; others are pure noise -> truth has the highest
      // expected probability but loses the per-view argmax often (~40 % of views).
      std::array<double, kClasses> prob{};
      double z = 0;
      for (int i = 0; i < kClasses; ++i) z += prob[i] = std::exp((i == truth ? GetParam().signal : 0.0) + noise(rng));
      LabelSet all;
      std::array<std::pair<double, int>, kClasses> order{};
      for (int i = 0; i < kClasses; ++i) order[i] = {-prob[i] / z, i};
      std::sort(order.begin(), order.end());
      for (int i = 0; i < 3; ++i) all.push(ClassId(order[i].second), float(-order[i].first));
      correct_obs += all.top() == truth;
      fusion_function(c.policy)(map, all, c);
    }
    EXPECT_LT(correct_obs, GetParam().max_correct_views) << "the test must be noisy enough to matter";
    EXPECT_EQ(map.top(), truth) << "policy " << to_string(GetParam().policy) << " seed " << seed;
  }
}

INSTANTIATE_TEST_SUITE_P(Policies, MappingFusionConvergence,
                         ::testing::Values(ConvergenceCase{FusionPolicy::kPaper, 0.8, 160},
                                           ConvergenceCase{FusionPolicy::kBayesian, 0.8, 160},
                                           ConvergenceCase{FusionPolicy::kMaxConfidence, 3.0, 195}),
                         [](const auto& info) { return to_string(info.param.policy); });
