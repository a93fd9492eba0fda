#pragma once
// The labelled clouds the pipeline has put into the map, kept (downsampled) with the keyframe they
// are anchored to, so that the map can be rebuilt whenever SLAM moves keyframes (loop closure,
// bundle adjustment) — as RTAB-Map does. A cloud's pose is T_w_c = T_w_kf * T_kf_c: keyframe clouds
// have T_kf_c = identity; clouds of other frames (integrate: all_frames) ride on the last keyframe.
#include <cstdint>
#include <map>
#include <vector>

#include "s3m/core/se3.hpp"
#include "s3m/pipeline/labelled_cloud.hpp"

namespace s3m::pipeline {

using KeyframeId = std::int64_t;  // same values as slam::KfId

struct KeptCloud {
  KeyframeId anchor = -1;      // keyframe the cloud moves with
  SE3 T_kf_c = SE3::Identity();
  int frame_index = 0;
  mapping::LabeledCloud cloud;  // camera frame (origin 0), exactly what was inserted
};

class KeyframeStore {
 public:
  // Records a keyframe and its pose as SLAM created it (every keyframe, so that corrections of
  // culled keyframes can be inferred from their neighbours).
  void note_keyframe(KeyframeId id, const SE3& T_w_kf) { keyframes_.insert_or_assign(id, T_w_kf); }
  // Keeps a cloud observed at T_w_c, anchored to the noted keyframe `anchor`.
  void add(KeyframeId anchor, const SE3& T_w_c, int frame_index, mapping::LabeledCloud cloud);

  // Moves anchors to new keyframe poses. Anchors not in the map (keyframes SLAM has culled since)
  // follow the correction of the nearest listed keyframe by id, which is the keyframe they were
  // spatially closest to in time. Returns the largest anchor translation change [m].
  double update_poses(const std::map<KeyframeId, SE3>& T_w_kf);

  std::size_t size() const { return clouds_.size(); }
  std::size_t bytes() const;
  const std::vector<KeptCloud>& clouds() const { return clouds_; }
  SE3 T_w_c(const KeptCloud& c) const { return keyframes_.at(c.anchor) * c.T_kf_c; }
  const std::map<KeyframeId, SE3>& keyframes() const { return keyframes_; }

 private:
  std::map<KeyframeId, SE3> keyframes_;  // current T_w_kf of every keyframe noted
  std::vector<KeptCloud> clouds_;      // insertion order (the order a rebuild re-inserts them)
};

}  // namespace s3m::pipeline
