#include "s3m/slam/loop/loop_keyframe_index.hpp"

#include "s3m/core/error.hpp"

namespace s3m::slam {

KeyFrameBowIndex::KeyFrameBowIndex(std::shared_ptr<const features::Vocabulary> vocabulary, int direct_level)
    : vocabulary_(std::move(vocabulary)), direct_level_(direct_level) {
  require(vocabulary_ && !vocabulary_->empty(),
          "KeyFrameBowIndex: an empty vocabulary cannot index keyframes");
  require(direct_level_ >= 0 && direct_level_ <= vocabulary_->levels(),
          "KeyFrameBowIndex: direct_level must be within the vocabulary's depth");
}

KeyFrameBow KeyFrameBowIndex::describe(const cv::Mat& descriptors) const {
  KeyFrameBow b;
  b.bow = vocabulary_->transform(descriptors, &b.direct, direct_level_);
  return b;
}

void KeyFrameBowIndex::sync(const Map& map) {
  for (auto it = entries_.begin(); it != entries_.end();) {
    if (map.has_keyframe(it->first)) {
      ++it;
    } else {
      db_.erase(int(it->first));
      it = entries_.erase(it);
    }
  }
  for (const auto& [id, kf] : map.keyframes()) {
    if (entries_.count(id) || !kf.features) continue;
    auto& e = entries_[id] = describe(kf.features->descriptors);
    db_.add(int(id), e.bow);
  }
}

void KeyFrameBowIndex::restore(KeyframeId id, KeyFrameBow bow) {
  db_.add(int(id), bow.bow);
  entries_[id] = std::move(bow);
}

const KeyFrameBow* KeyFrameBowIndex::find(KeyframeId id) const {
  const auto it = entries_.find(id);
  return it == entries_.end() ? nullptr : &it->second;
}

}  // namespace s3m::slam
