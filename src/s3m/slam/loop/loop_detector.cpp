#include "s3m/slam/loop/loop_detector.hpp"

#include <algorithm>
#include <unordered_map>

#include "s3m/core/error.hpp"

namespace s3m::slam {

void LoopDetectorConfig::validate() const {
  require(min_common_words_ratio > 0 && min_common_words_ratio <= 1,
          "loop.min_common_words_ratio must be in (0, 1]");
  require(group_score_ratio > 0 && group_score_ratio <= 1, "loop.group_score_ratio must be in (0, 1]");
  require(group_neighbours >= 0 && consistency >= 0, "loop: group_neighbours and consistency must be >= 0");
}

LoopDetector::LoopDetector(const LoopDetectorConfig& config) : config_(config) { config_.validate(); }

std::vector<KeyframeId> LoopDetector::detect(const Map& map, const KeyFrameBowIndex& index,
                                             KeyframeId kf_id) {
  const KeyFrame& kf = map.keyframe(kf_id);
  const KeyFrameBow* q = index.find(kf_id);
  require(q != nullptr, "LoopDetector::detect: keyframe not in the BoW index");

  // 1. The query's worst covisible neighbour sets the bar a loop candidate has to clear.
  double min_score = 1.0;
  for (const auto& [n, w] : kf.covisibility) {
    if (const KeyFrameBow* b = index.find(n))
      min_score = std::min(min_score, features::l1_score(q->bow, b->bow));
  }
  if (kf.covisibility.empty()) min_score = 0.0;

  // 2. Database candidates: not the keyframe itself nor covisible with it, enough common words.
  const auto hits = index.database().query(q->bow, 0, [&](int id) {
    return KeyframeId(id) != kf_id && kf.covisibility.count(KeyframeId(id)) == 0 &&
           map.has_keyframe(KeyframeId(id));
  });
  int max_common = 0;
  for (const auto& h : hits) max_common = std::max(max_common, h.common_words);
  std::unordered_map<KeyframeId, double> score;
  for (const auto& h : hits) {
    if (h.common_words >= config_.min_common_words_ratio * max_common && h.score >= min_score)
      score[KeyframeId(h.entry_id)] = h.score;
  }

  // 3. Accumulate each candidate's score over its covisible neighbours that are candidates too;
  //    the group's best-scoring member represents it.
  struct Acc {
    KeyframeId best;
    double total;
  };
  std::vector<Acc> groups;
  double best_total = 0.0;
  for (const auto& [id, s] : score) {
    Acc a{id, s};
    double best_member = s;
    for (KeyframeId n : map.keyframe(id).best_covisible(config_.group_neighbours)) {
      const auto it = score.find(n);
      if (it == score.end()) continue;
      a.total += it->second;
      if (it->second > best_member) best_member = it->second, a.best = n;
    }
    best_total = std::max(best_total, a.total);
    groups.push_back(a);
  }
  std::sort(groups.begin(), groups.end(), [](const Acc& a, const Acc& b) {
    return a.total != b.total ? a.total > b.total : a.best < b.best;
  });
  std::vector<KeyframeId> candidates;
  for (const Acc& a : groups) {
    if (a.total >= config_.group_score_ratio * best_total &&
        std::find(candidates.begin(), candidates.end(), a.best) == candidates.end())
      candidates.push_back(a.best);
  }
  // 4. Temporal consistency.
  return consistent(map, candidates);
}

std::vector<KeyframeId> LoopDetector::consistent(const Map& map, const std::vector<KeyframeId>& candidates) {
  std::vector<Group> next;
  std::vector<char> extended(groups_.size(), 0);
  std::vector<KeyframeId> accepted;
  for (KeyframeId c : candidates) {
    Group g;
    g.members.insert(c);
    for (const auto& [n, w] : map.keyframe(c).covisibility) g.members.insert(n);
    bool continues = false;
    for (size_t i = 0; i < groups_.size(); ++i) {
      const bool overlap = std::any_of(g.members.begin(), g.members.end(),
                                       [&](KeyframeId m) { return groups_[i].members.count(m) > 0; });
      if (!overlap) continue;
      continues = true;
      const int count = groups_[i].consistency + 1;
      if (!extended[i]) {
        next.push_back({g.members, count});
        extended[i] = 1;
      }
      if (count >= config_.consistency && std::find(accepted.begin(), accepted.end(), c) == accepted.end())
        accepted.push_back(c);
    }
    if (!continues) {
      next.push_back({g.members, 0});
      if (config_.consistency == 0) accepted.push_back(c);
    }
  }
  groups_ = std::move(next);
  return accepted;
}

}  // namespace s3m::slam
