#include "s3m/features/bow_matcher.hpp"

#include "s3m/core/error.hpp"

namespace s3m::features {

void BowMatchConfig::validate() const {
  require(max_hamming >= 0 && max_hamming <= 256, "BowMatchConfig.max_hamming must be in [0, 256]");
  require(ratio > 0.0 && ratio <= 1.0, "BowMatchConfig.ratio must be in (0, 1]");
}

std::vector<std::pair<int, int>> match_by_bow(const FeatureVector& fv_a, const cv::Mat& desc_a, const FeatureVector& fv_b,
                                              const cv::Mat& desc_b, const BowMatchConfig& config,
                                              const std::vector<bool>& usable_b) {
  config.validate();
  require_orb_descriptors(desc_a, "match_by_bow");
  require_orb_descriptors(desc_b, "match_by_bow");
  // Best candidate per b feature, so a b feature claimed twice keeps the closer a feature.
  std::vector<int> best_a_for_b(size_t(desc_b.rows), -1);
  std::vector<int> best_dist_for_b(size_t(desc_b.rows), 257);
  auto ia = fv_a.begin();
  auto ib = fv_b.begin();
  while (ia != fv_a.end() && ib != fv_b.end()) {
    if (ia->first < ib->first) {
      ++ia;
      continue;
    }
    if (ib->first < ia->first) {
      ++ib;
      continue;
    }
    for (int i : ia->second) {
      const Descriptor256 da = descriptor_from_row(desc_a, i);
      int best = 257, second = 257, best_j = -1;
      for (int j : ib->second) {
        if (!usable_b.empty() && !usable_b[size_t(j)]) continue;
        const int d = hamming(da, descriptor_from_row(desc_b, j));
        if (d < best) {
          second = best;
          best = d;
          best_j = j;
        } else if (d < second) {
          second = d;
        }
      }
      if (best_j < 0 || best > config.max_hamming) continue;
      if (second <= 256 && double(best) > config.ratio * double(second)) continue;
      if (best < best_dist_for_b[size_t(best_j)]) {
        best_dist_for_b[size_t(best_j)] = best;
        best_a_for_b[size_t(best_j)] = i;
      }
    }
    ++ia;
    ++ib;
  }
  std::vector<std::pair<int, int>> matches;
  for (int j = 0; j < desc_b.rows; ++j) {
    if (best_a_for_b[size_t(j)] >= 0) matches.emplace_back(best_a_for_b[size_t(j)], j);
  }
  return matches;
}

}  // namespace s3m::features
