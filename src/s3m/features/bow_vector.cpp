#include "s3m/features/bow_vector.hpp"

#include <algorithm>
#include <cstring>
#include <string>

#include "s3m/core/error.hpp"

namespace s3m::features {

void require_orb_descriptors(const cv::Mat& descriptors, const char* context) {
  if (descriptors.empty()) return;
  if (descriptors.type() != CV_8UC1 || descriptors.cols != 32) {
    throw Error(std::string(context) + ": descriptors must be CV_8UC1 with 32 columns (256-bit ORB), got type " +
                std::to_string(descriptors.type()) + " with " + std::to_string(descriptors.cols) + " columns");
  }
}

Descriptor256 descriptor_from_row(const cv::Mat& descriptors, int row) {
  require_orb_descriptors(descriptors, "descriptor_from_row");
  require(row >= 0 && row < descriptors.rows, "descriptor_from_row: row out of range");
  Descriptor256 d;
  std::memcpy(d.data(), descriptors.ptr<uint8_t>(row), 32);
  return d;
}

void normalize_l1(BowVector& v) {
  double sum = 0.0;
  for (const auto& [w, x] : v) sum += std::abs(x);
  if (sum <= 0.0) return;
  for (auto& [w, x] : v) x /= sum;
}

double l1_score(const BowVector& a, const BowVector& b) {
  double score = 0.0;
  auto ia = a.begin();
  auto ib = b.begin();
  while (ia != a.end() && ib != b.end()) {
    if (ia->first < ib->first) {
      ia = a.lower_bound(ib->first);
    } else if (ib->first < ia->first) {
      ib = b.lower_bound(ia->first);
    } else {
      score += std::min(ia->second, ib->second);
      ++ia;
      ++ib;
    }
  }
  return score;
}

}  // namespace s3m::features
