#pragma once
// Bag-of-words vectors and descriptors for place recognition, following DBoW2's conventions:
// TF-IDF word weights, L1-normalised vectors, L1 score in [0, 1].
#include <array>
#include <cstdint>
#include <map>
#include <vector>

#include <opencv2/core.hpp>

namespace s3m::features {

using WordId = uint32_t;
using NodeId = uint32_t;

// A 256-bit binary descriptor (ORB/rBRIEF) packed in four 64-bit words for popcount distances.
using Descriptor256 = std::array<uint64_t, 4>;

// Hamming distance in bits, 0..256.
inline int hamming(const Descriptor256& a, const Descriptor256& b) {
  return __builtin_popcountll(a[0] ^ b[0]) + __builtin_popcountll(a[1] ^ b[1]) +
         __builtin_popcountll(a[2] ^ b[2]) + __builtin_popcountll(a[3] ^ b[3]);
}

// Row `row` of a CV_8U descriptor matrix with 32 columns. Throws s3m::Error on another layout.
Descriptor256 descriptor_from_row(const cv::Mat& descriptors, int row);
// Checks the layout OpenCV's ORB produces (CV_8UC1, 32 columns); throws s3m::Error otherwise.
void require_orb_descriptors(const cv::Mat& descriptors, const char* context);

// Sparse word histogram: word id -> TF-IDF weight, L1-normalised (weights sum to 1).
using BowVector = std::map<WordId, double>;

// Direct index: vocabulary node at a fixed tree level -> indices of the image's features below
// it. Matching only features that share a node is what makes BoW-accelerated matching fast.
using FeatureVector = std::map<NodeId, std::vector<int>>;

// Scales v so its weights sum to 1 (no-op for an empty vector).
void normalize_l1(BowVector& v);

// DBoW2's L1 score 1 - 0.5 * |a - b|_1 for L1-normalised vectors: 1 = identical, 0 = no common
// word. For normalised vectors this equals the sum over common words of min(a_i, b_i).
double l1_score(const BowVector& a, const BowVector& b);

}  // namespace s3m::features
