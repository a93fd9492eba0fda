#pragma once
// Descriptor matching accelerated by the vocabulary's direct index (ORB-SLAM's SearchByBoW):
// only features under the same vocabulary node are compared.
#include <utility>
#include <vector>

#include <opencv2/core.hpp>

#include "s3m/features/bow_vector.hpp"

namespace s3m::features {

struct BowMatchConfig {
  int max_hamming = 50;      // bits; ORB-SLAM's TH_LOW
  double ratio = 0.75;       // best / second-best distance (Lowe's test); 1 disables it
  void validate() const;
};

// Matches (index in a, index in b), each feature used at most once on both sides.
// `usable_b(j)` filters b's features (e.g. only those with a map point); empty = all.
std::vector<std::pair<int, int>> match_by_bow(const FeatureVector& fv_a, const cv::Mat& desc_a, const FeatureVector& fv_b,
                                              const cv::Mat& desc_b, const BowMatchConfig& config = {},
                                              const std::vector<bool>& usable_b = {});

}  // namespace s3m::features
