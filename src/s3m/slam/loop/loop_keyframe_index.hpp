#pragma once
// BoW view of the map's keyframes for loop detection and relocalisation: per keyframe its BoW
// vector and direct index (computed once from its descriptors), plus the inverted-index database.
// Kept in step with the Map by sync(): new keyframes are added, culled ones dropped.
#include <map>
#include <memory>

#include "s3m/features/bow_database.hpp"
#include "s3m/features/bow_vocabulary.hpp"
#include "s3m/slam/map/map.hpp"

namespace s3m::slam {

struct KeyFrameBow {
  features::BowVector bow;
  features::FeatureVector direct;  // vocabulary node at direct_level -> keypoint indices
};

class KeyFrameBowIndex {
 public:
  // direct_level: tree level (below the root) of the direct index used for BoW matching.
  KeyFrameBowIndex(std::shared_ptr<const features::Vocabulary> vocabulary, int direct_level = 2);

  // Adds keyframes the index has not seen and removes those no longer in the map.
  void sync(const Map& map);
  // Indexes keyframe id with a BoW computed earlier (a loaded map) instead of recomputing it.
  void restore(KeyframeId id, KeyFrameBow bow);
  // BoW of any descriptor set (a frame being relocalised).
  KeyFrameBow describe(const cv::Mat& descriptors) const;

  const KeyFrameBow* find(KeyframeId id) const;
  const features::BowDatabase& database() const { return db_; }
  const features::Vocabulary& vocabulary() const { return *vocabulary_; }
  int direct_level() const { return direct_level_; }
  size_t size() const { return entries_.size(); }

 private:
  std::shared_ptr<const features::Vocabulary> vocabulary_;
  int direct_level_;
  std::map<KeyframeId, KeyFrameBow> entries_;
  features::BowDatabase db_;
};

}  // namespace s3m::slam
