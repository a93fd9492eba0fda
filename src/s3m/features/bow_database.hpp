#pragma once
// Inverted-index image database over BoW vectors (DBoW2's Database): for each word, the entries
// (keyframes) that contain it, so a query touches only entries sharing at least one word.
#include <functional>
#include <unordered_map>
#include <vector>

#include "s3m/features/bow_vector.hpp"

namespace s3m::features {

struct BowQueryResult {
  int entry_id = -1;
  double score = 0.0;    // L1 score in [0, 1]
  int common_words = 0;  // words shared with the query
};

class BowDatabase {
 public:
  // Adds (or replaces) an entry; ids are the caller's (e.g. keyframe ids), any int >= 0.
  void add(int entry_id, const BowVector& v);
  // Removes an entry (culled keyframe); unknown ids are ignored.
  void erase(int entry_id);
  void clear();
  size_t size() const { return entries_.size(); }
  bool contains(int entry_id) const { return entries_.count(entry_id) > 0; }
  const BowVector& vector_of(int entry_id) const { return entries_.at(entry_id); }

  // Entries sharing a word with q, best L1 score first, at most max_results (0 = all), keeping
  // only those `accept` returns true for (e.g. not covisible with the query keyframe).
  std::vector<BowQueryResult> query(const BowVector& q, size_t max_results = 0,
                                    const std::function<bool(int)>& accept = {}) const;

 private:
  struct Posting {
    int entry_id;
    double weight;
  };
  std::unordered_map<WordId, std::vector<Posting>> inverted_;
  std::unordered_map<int, BowVector> entries_;
};

}  // namespace s3m::features
