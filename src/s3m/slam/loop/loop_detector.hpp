#pragma once
// Loop candidates from the BoW database (ORB-SLAM's DetectLoop): keyframes not covisible with the
// query that score at least as well as its worst covisible neighbour, grouped with their own
// covisible neighbours, and kept only when consistent over several consecutive keyframes.
#include <set>
#include <vector>

#include "s3m/slam/loop/loop_keyframe_index.hpp"
#include "s3m/slam/map/map.hpp"

namespace s3m::slam {

struct LoopDetectorConfig {
  double min_common_words_ratio = 0.8;  // of the best candidate's common words
  double group_score_ratio = 0.75;      // of the best accumulated group score
  int group_neighbours = 10;            // covisible keyframes that join a candidate's group
  int consistency = 3;                  // consecutive keyframes a group must be seen in
  void validate() const;
};

class LoopDetector {
 public:
  explicit LoopDetector(const LoopDetectorConfig& config = {});
  // Candidates for keyframe kf (must be in map and index), best first. Updates the consistency
  // state, so call it once per new keyframe, in order.
  std::vector<KeyframeId> detect(const Map& map, const KeyFrameBowIndex& index, KeyframeId kf);
  void reset() { groups_.clear(); }

 private:
  struct Group {
    std::set<KeyframeId> members;
    int consistency = 0;
  };
  std::vector<KeyframeId> consistent(const Map& map, const std::vector<KeyframeId>& candidates);

  LoopDetectorConfig config_;
  std::vector<Group> groups_;
};

}  // namespace s3m::slam
