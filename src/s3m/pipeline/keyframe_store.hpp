#pragma once
// The labelled clouds the pipeline has put into the map, kept (downsampled) with the keyframe they
// are anchored to, so that the map can be rebuilt whenever SLAM moves keyframes (loop closure,
// bundle adjustment) — as RTAB-Map does. A cloud's pose is T_w_c = T_w_kf * T_kf_c: keyframe clouds
// have T_kf_c = identity; clouds of other frames (integrate: all_frames) ride on the last keyframe.
//
// Memory budget: a long run over the same area would keep one cloud per integrated frame forever
// (~0.1-0.2 MB each at 5 cm). With a budget, once the kept clouds exceed it the most redundant cloud
// is dropped: the oldest cloud of the most crowded viewpoint cell (camera position in 0.5 m cells,
// viewing direction in ~30 deg cells), keyframe clouds only when a cell has nothing else. Dropped
// clouds stay in the live map; a later rebuild re-inserts only the kept ones, i.e. revisits of a
// place contribute their newest views. The map itself is bounded by the area, not by time.
#include <cstdint>
#include <map>
#include <set>
#include <vector>

#include "s3m/core/keyframe_id.hpp"
#include "s3m/core/se3.hpp"
#include "s3m/mapping/labeled_cloud.hpp"

namespace s3m::pipeline {

struct KeptCloud {
  KeyframeAnchor anchor;  // keyframe the cloud moves with, and the camera pose relative to it
  int frame_index = 0;
  mapping::LabeledCloud cloud;  // camera frame (origin 0), exactly what was inserted
  // Which recording session observed it: 0 for the clouds of a loaded map (a saved run, whatever
  // it was merged from), then one number per session added on top (start_session()). Not saved:
  // a run that is saved and loaded again is one session.
  int session = 0;
};

class KeyframeStore {
 public:
  // budget_bytes = 0: unlimited (every cloud is kept).
  explicit KeyframeStore(std::size_t budget_bytes = 0) : budget_bytes_(budget_bytes) {}

  // Records a keyframe and its pose as SLAM created it (every keyframe, so that corrections of
  // culled keyframes can be inferred from their neighbours). detached: the keyframe is in a SLAM
  // sub-map outside the world (TrackOutput::detached), T_w_kf in that sub-map's frame; its clouds
  // are kept but left out of the map until update_poses() lists it.
  void note_keyframe(KeyframeId id, const SE3& T_w_kf, bool detached = false);
  // Clouds added from now on belong to a new session (a run continuing a loaded map).
  void start_session() { session_ = next_session(); }
  // Keeps a cloud of the current session observed at T_w_c, anchored to the noted keyframe
  // `keyframe`; then drops redundant clouds while over budget (never the one just added).
  void add(KeyframeId keyframe, const SE3& T_w_c, int frame_index, mapping::LabeledCloud cloud);
  // Keeps a cloud exactly as another run's store held it (a loaded session); its keyframe must
  // have been noted. The budget applies as in add().
  void add_kept(KeptCloud kept);

  // Moves anchors to new keyframe poses. Anchors not in the map (keyframes SLAM has culled since)
  // follow the correction of the nearest listed keyframe by id, which is the keyframe they were
  // spatially closest to in time. Listed detached keyframes join the world. Returns the largest
  // anchor translation change [m] (infinity when a keyframe holding clouds joined the world).
  double update_poses(const std::map<KeyframeId, SE3>& T_w_kf);
  // The world is now exactly the listed keyframes (SLAM made another sub-map the world at the end):
  // they take these poses and join it; every other noted keyframe leaves it (its clouds are kept,
  // not mapped).
  void set_world(const std::map<KeyframeId, SE3>& T_w_kf);
  // Whether a cloud (its keyframe) is in the world: what a rebuild inserts and a session saves.
  bool in_world(KeyframeId id) const { return detached_.count(id) == 0; }
  bool in_world(const KeptCloud& c) const { return in_world(c.anchor.keyframe); }

  // Sessions of the clouds in the world, ascending.
  std::set<int> sessions_in_world() const;
  std::size_t size() const { return clouds_.size(); }
  std::size_t bytes() const { return bytes_; }
  std::size_t budget_bytes() const { return budget_bytes_; }
  std::size_t dropped() const { return dropped_; }  // clouds dropped to stay within the budget
  const std::vector<KeptCloud>& clouds() const { return clouds_; }
  SE3 T_w_c(const KeyframeAnchor& a) const { return keyframes_.at(a.keyframe) * a.T_kf_c; }
  SE3 T_w_c(const KeptCloud& c) const { return T_w_c(c.anchor); }
  const std::map<KeyframeId, SE3>& keyframes() const { return keyframes_; }

 private:
  void drop_most_redundant();
  int next_session() const;

  std::map<KeyframeId, SE3> keyframes_;  // current T_w_kf of every keyframe noted
  std::set<KeyframeId> detached_;        // noted keyframes outside the world (not listed yet)
  std::vector<KeptCloud> clouds_;      // insertion order (the order a rebuild re-inserts them)
  int session_ = 0;                    // session of the clouds add() keeps
  std::size_t budget_bytes_ = 0;
  std::size_t bytes_ = 0;
  std::size_t dropped_ = 0;
};

}  // namespace s3m::pipeline
