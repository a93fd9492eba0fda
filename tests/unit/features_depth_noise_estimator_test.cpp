// What tracking learns about the depth sensor: robust sigma per depth bin, the sigma(z) fit, the
// colour-depth offsets, on residuals drawn from a known curve (fixed seed).
#include <random>

#include <gtest/gtest.h>

#include "s3m/features/depth_noise_estimator.hpp"

namespace s3m::features {
namespace {

// sigma(z) = 2 mm + 3 mm/m^2 z^2 at depths 0.5-4 m; 5 % of the residuals are wild (a wrong match's
// depth), which the MAD ignores and a standard deviation would not.
TEST(DepthNoiseEstimator, RecoversAKnownCurveDespiteOutliers) {
  DepthNoiseEstimator est;
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> depth(0.5, 4.0), wild(-0.5, 0.5), unit(0, 1);
  std::normal_distribution<double> gauss(0, 1);
  for (int i = 0; i < 40000; ++i) {
    const double z = depth(rng), sigma = 0.002 + 0.003 * z * z;
    const double r = unit(rng) < 0.05 ? wild(rng) : sigma * gauss(rng);
    est.add(z + r, z);
  }
  const DepthNoiseEstimate e = est.estimate();
  EXPECT_EQ(e.samples, 40000);
  ASSERT_EQ(e.bins.size(), 7u);  // 0.5-1, ..., 3.5-4 m
  for (const auto& b : e.bins) {
    const double truth = 0.002 + 0.003 * b.z_m * b.z_m;
    EXPECT_NEAR(b.sigma_m, truth, 0.12 * truth) << b.z_m;  // bin-width spread and the 5 % wild ones
  }
  ASSERT_TRUE(e.fitted);
  EXPECT_NEAR(e.k_per_m, 0.003, 0.0004);
  EXPECT_NEAR(e.sigma0_m, 0.002, 0.001);
  EXPECT_NEAR(e.sigma_at(2.0), 0.014, 0.0015);
  EXPECT_EQ(e.offset_frames, 0);
}

// A curve flat in z: the free fit's k would be ~0 or negative, and neither coefficient may be.
TEST(DepthNoiseEstimator, AFlatCurveFitsWithoutNegativeCoefficients) {
  DepthNoiseEstimator est;
  std::mt19937 rng(3);
  std::normal_distribution<double> gauss(0, 0.004);
  for (int i = 0; i < 3000; ++i) est.add(1.2 + gauss(rng), 1.2);
  for (int i = 0; i < 3000; ++i) est.add(2.7 + gauss(rng), 2.7);
  const DepthNoiseEstimate e = est.estimate();
  ASSERT_TRUE(e.fitted);
  EXPECT_GE(e.k_per_m, 0.0);
  EXPECT_GE(e.sigma0_m, 0.0);
  EXPECT_NEAR(e.sigma_at(1.2), 0.004, 0.0006);
  EXPECT_NEAR(e.sigma_at(2.7), 0.004, 0.0006);
}

// Bins with too few residuals are left out; one bin is no curve; the ring buffer keeps the newest.
TEST(DepthNoiseEstimator, SparseBinsAndTheNewestResiduals) {
  DepthNoiseEstimator est(0.5, 6.0, 99);
  const double step[] = {-1.0, 0.0, 1.0};          // a third each: median 0, median |r| = the step
  for (int i = 0; i < 49; ++i) est.add(3.1, 3.0);  // under the 50 a bin needs
  for (int i = 0; i < 99; ++i) est.add(1.0 + 0.05 * step[i % 3], 1.0);
  DepthNoiseEstimate e = est.estimate();
  ASSERT_EQ(e.bins.size(), 1u);
  EXPECT_FALSE(e.fitted);
  EXPECT_DOUBLE_EQ(e.bins[0].z_m, 1.25);
  EXPECT_NEAR(e.bins[0].sigma_m, 1.4826 * 0.05, 1e-6);
  for (int i = 0; i < 99; ++i) est.add(1.0 + 0.01 * step[i % 3], 1.0);  // overwrites all 99
  e = est.estimate();
  EXPECT_EQ(e.bins[0].n, 99);
  EXPECT_NEAR(e.bins[0].sigma_m, 1.4826 * 0.01, 1e-6);
  EXPECT_EQ(e.samples, 247);
  est.add(7.0, 7.0);  // beyond max depth: not counted
  est.add(0.0, 1.0);  // no depth
  EXPECT_EQ(est.estimate().samples, 247);
}

TEST(DepthNoiseEstimator, ColourDepthOffsets) {
  DepthNoiseEstimator est;
  for (double dt : {0.0, 0.012, -0.020, 0.015, 0.0, 0.014}) est.add_offset(dt);
  const DepthNoiseEstimate e = est.estimate();
  EXPECT_EQ(e.offset_frames, 4);  // the synchronised frames are not offsets
  EXPECT_NEAR(e.offset_median_s, 0.014, 1e-7);
  EXPECT_NEAR(e.offset_max_abs_s, 0.020, 1e-7);
  EXPECT_NE(describe(e).find("offset median 14.0 ms (largest 20.0 ms) in 4 frames"), std::string::npos)
      << describe(e);
}

}  // namespace
}  // namespace s3m::features
