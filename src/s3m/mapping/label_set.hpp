#pragma once
// Top-k class labels with probabilities, as stored in a map voxel and carried by an observation.
// Invariant after normalise(): labels sorted by probability (descending), ties by class id
// (ascending), at most k entries, no duplicates. The mass 1 - sum() is the implicit "other" bin
// (the paper's p-bar): everything the top-k does not name.
#include <array>
#include <cstdint>

#include "s3m/core/classes.hpp"

namespace s3m::mapping {

// Hard upper bound on k (the project-wide kMaxTopK); the tree-level k (default 3) may be anything in
// [1, kMaxLabels]. Small and fixed so a voxel stays a flat 40-byte payload with no heap allocation.
inline constexpr int kMaxLabels = kMaxTopK;

struct LabelSet {
  std::uint8_t n = 0;
  std::array<ClassId, kMaxLabels> ids{};
  std::array<float, kMaxLabels> probs{};

  bool empty() const { return n == 0; }
  ClassId top() const { return n ? ids[0] : cls::kUnknown; }
  float top_prob() const { return n ? probs[0] : 0.0f; }
  float sum() const;
  int find(ClassId id) const;  // index or -1
  float prob_of(ClassId id) const;
  bool push(ClassId id, float p);  // false when full
  // Sort (prob desc, id asc), merge duplicate ids (summing), drop p <= 0, keep the first k.
  void normalise(int k);

  bool operator==(const LabelSet& o) const;
  bool operator!=(const LabelSet& o) const { return !(*this == o); }
};

}  // namespace s3m::mapping
