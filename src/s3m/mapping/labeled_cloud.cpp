#include "s3m/mapping/labeled_cloud.hpp"

#include "s3m/core/error.hpp"
#include "s3m/mapping/label_set.hpp"

namespace s3m::mapping {

void LabeledCloud::reserve(std::size_t n) {
  points.reserve(n);
  rgb.reserve(3 * n);
  labels.reserve(std::size_t(k) * n);
  probs.reserve(std::size_t(k) * n);
}

void LabeledCloud::shrink_to_fit() {
  points.shrink_to_fit();
  rgb.shrink_to_fit();
  labels.shrink_to_fit();
  probs.shrink_to_fit();
}

void LabeledCloud::push_back(const Eigen::Vector3f& p, std::uint8_t r, std::uint8_t g, std::uint8_t b,
                             const ClassId* point_labels, const float* point_probs) {
  points.push_back(p);
  rgb.insert(rgb.end(), {r, g, b});
  for (int j = 0; j < k; ++j) {
    labels.push_back(point_labels ? point_labels[j] : cls::kUnknown);
    probs.push_back(point_probs ? point_probs[j] : 0.0f);
  }
}

void LabeledCloud::validate() const {
  const std::size_t n = points.size();
  require(k >= 0 && k <= kMaxLabels, "LabeledCloud: k must be in [0, " + std::to_string(kMaxLabels) + "]");
  require(rgb.empty() || rgb.size() == 3 * n, "LabeledCloud: rgb must be empty or hold 3 bytes per point (" +
                                                  std::to_string(rgb.size()) + " for " + std::to_string(n) + " points)");
  require(labels.size() == std::size_t(k) * n && probs.size() == labels.size(),
          "LabeledCloud: labels and probs must hold k = " + std::to_string(k) + " entries per point");
}

}  // namespace s3m::mapping
