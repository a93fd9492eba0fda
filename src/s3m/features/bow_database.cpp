#include "s3m/features/bow_database.hpp"

#include <algorithm>

#include "s3m/core/error.hpp"

namespace s3m::features {

void BowDatabase::add(int entry_id, const BowVector& v) {
  require(entry_id >= 0, "BowDatabase::add: entry ids must be >= 0");
  erase(entry_id);
  entries_[entry_id] = v;
  for (const auto& [w, x] : v) inverted_[w].push_back({entry_id, x});
}

void BowDatabase::erase(int entry_id) {
  auto it = entries_.find(entry_id);
  if (it == entries_.end()) return;
  for (const auto& [w, x] : it->second) {
    auto& postings = inverted_[w];
    std::erase_if(postings, [&](const Posting& p) { return p.entry_id == entry_id; });
    if (postings.empty()) inverted_.erase(w);
  }
  entries_.erase(it);
}

void BowDatabase::clear() {
  inverted_.clear();
  entries_.clear();
}

std::vector<BowQueryResult> BowDatabase::query(const BowVector& q, size_t max_results,
                                               const std::function<bool(int)>& accept) const {
  // For L1-normalised vectors the L1 score is the sum of min(q_i, e_i) over common words, so it
  // accumulates from the posting lists alone (see l1_score).
  std::unordered_map<int, BowQueryResult> hits;
  for (const auto& [w, qx] : q) {
    auto it = inverted_.find(w);
    if (it == inverted_.end()) continue;
    for (const Posting& p : it->second) {
      if (accept && !accept(p.entry_id)) continue;
      auto& h = hits[p.entry_id];
      h.entry_id = p.entry_id;
      h.score += std::min(qx, p.weight);
      h.common_words++;
    }
  }
  std::vector<BowQueryResult> results;
  results.reserve(hits.size());
  for (const auto& [id, h] : hits) results.push_back(h);
  std::sort(results.begin(), results.end(), [](const BowQueryResult& a, const BowQueryResult& b) {
    return a.score != b.score ? a.score > b.score : a.entry_id < b.entry_id;
  });
  if (max_results > 0 && results.size() > max_results) results.resize(max_results);
  return results;
}

}  // namespace s3m::features
