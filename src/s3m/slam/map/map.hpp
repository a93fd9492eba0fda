#pragma once
// The SLAM map: the single owner of keyframes, map points and the covisibility graph.
// Whoever holds the Map (the local-mapping stage; in threaded mode its thread) is the only one
// that reads or writes it, so there are no per-accessor locks. Other stages get copies
// (LocalMapSnapshot) through queues. Every mutation goes through a method that keeps both sides
// of an observation (keyframe slot <-> point) consistent.
//
// Hooks for loop closing / relocalisation (part 2): keyframes expose their features
// (descriptors, keypoints, depth) and matched point per keypoint; covisibility weights and the
// spanning tree (parent/children) are kept up to date; apply_corrected_poses() moves keyframes
// and their points to corrected poses.
#include <map>
#include <memory>
#include <set>
#include <vector>

#include "s3m/core/se3.hpp"
#include "s3m/features/frame_features.hpp"
#include "s3m/slam/map/types.hpp"

namespace s3m::slam {

struct MapPoint {
  PointId id = kNoId;
  Vec3 p_w = Vec3::Zero();                 // position in the world [m]
  Descriptor descriptor{};                 // most representative (median) descriptor of its observations
  Vec3 normal_w = Vec3::UnitZ();           // mean viewing direction (unit)
  double min_dist_m = 0, max_dist_m = 0;   // distance range in which ORB can re-detect it
  std::map<KeyframeId, int> observations;  // keyframe -> keypoint index
  KeyframeId ref_kf = kNoId;               // keyframe it was created from (moves with it on correction)
  int n_visible = 1, n_found = 1;          // times predicted in view / actually matched by tracking
  bool bad = false;

  double found_ratio() const { return static_cast<double>(n_found) / n_visible; }
};

struct KeyFrame {
  KeyframeId id = kNoId;
  int frame_index = 0;                                      // index of the source frame in the sequence
  double t_s = 0;                                           // timestamp [s]
  SE3 T_w_c = SE3::Identity();                              // camera-to-world
  std::shared_ptr<const features::FrameFeatures> features;  // immutable, shared with other stages
  std::vector<PointId> points;                              // per keypoint: observed map point or kNoId
  std::map<KeyframeId, int> covisibility;                   // neighbour -> number of shared map points
  KeyframeId parent = kNoId;  // spanning tree (strongest covisible older keyframe)
  std::set<KeyframeId> children;
  // The first keyframe of a sub-map, the root of its tree: it defines that sub-map's world, so
  // every BA holds it and culling keeps it.
  bool is_root() const { return parent == kNoId; }
  // The sub-map (world frame) the keyframe belongs to: 0 is the world (the first map of the
  // session, or the loaded one); a session that cannot relocalise starts sub-map 1, 2, ... in a
  // frame of its own until a merge moves it into an older one (map_merge.hpp). Not saved: only the
  // world is (Map::keep_only_submap).
  int submap = 0;

  // Neighbours sorted by decreasing weight (ties: smaller id first), at most n (n < 0: all).
  std::vector<KeyframeId> best_covisible(int n = -1, int min_weight = 1) const;
  int n_tracked_points(int min_obs, const std::map<PointId, MapPoint>& points) const;
};

class Map {
 public:
  // Adds a keyframe (its points vector must be sized to its features, entries kNoId or existing
  // points, which get the observation). Returns the new id.
  KeyframeId add_keyframe(KeyFrame kf);
  // Creates a point observed at keyframe kf, keypoint idx. Returns the new id.
  PointId add_point(const Vec3& p_w, KeyframeId kf, int idx);

  void add_observation(PointId pid, KeyframeId kf, int idx);
  void erase_observation(PointId pid, KeyframeId kf);  // erases the point when too few observations remain
  // Merges `old_id` into `keep_id` (fusion of duplicates): observations move to keep_id.
  void replace_point(PointId old_id, PointId keep_id);
  void erase_point(PointId pid);
  // Removes a redundant keyframe; its children are re-parented; its pose relative to the parent is
  // remembered so frame poses referencing it can still be resolved.
  void erase_keyframe(KeyframeId id);

  // Recomputes kf's covisibility edges (and the neighbours' reverse edges); sets the spanning-tree
  // parent of a new keyframe.
  void update_covisibility(KeyframeId id);
  // Recomputes descriptor, normal and distance range of a point from its observations.
  void update_point_appearance(PointId pid);

  void set_keyframe_pose(KeyframeId id, const SE3& T_w_c) { keyframes_.at(id).T_w_c = T_w_c; }
  void set_point_position(PointId pid, const Vec3& p_w) { points_.at(pid).p_w = p_w; }
  void count_visible(PointId pid, int n_visible, int n_found);

  // Loop-closure correction: sets the given keyframe poses and moves every point rigidly with its
  // reference keyframe (if that keyframe was corrected).
  void apply_corrected_poses(const std::map<KeyframeId, SE3>& T_w_c_corrected);

  // Pose of keyframe id, following the culled-keyframe chain when it was erased.
  SE3 resolve_T_w_kf(KeyframeId id) const;

  // Sub-maps (map_submaps.cpp). The sub-map of a live or culled keyframe.
  int submap_of(KeyframeId id) const;
  int n_keyframes_in(int submap) const;
  // Merge: moves every keyframe and point of sub-map `from` by T_to_from (rigidly, into the frame
  // of sub-map `to`) and makes them members of `to`.
  void move_submap(int from, int to, const SE3& T_to_from);
  // Exchanges the labels of two sub-maps (no pose changes: each keeps its own frame). Making
  // another sub-map the world is relabelling it 0.
  void swap_submaps(int a, int b);
  // Culled keyframes of a sub-map with their poses (resolve_T_w_kf): what a consumer of keyframe
  // poses needs besides the live ones when a whole sub-map enters the world.
  std::map<KeyframeId, SE3> culled_poses_in(int submap) const;
  // Hangs kf's spanning tree below new_parent: the path from kf up to its root is reversed, so kf's
  // old root becomes an ordinary member of new_parent's tree.
  void join_tree(KeyframeId kf, KeyframeId new_parent);
  // Erases every keyframe (and the points only they observe) of the other sub-maps, and culled
  // keyframes that no longer resolve. What is saved when a session ends with unmerged sub-maps.
  void keep_only_submap(int submap);
  // Copies every keyframe, point and culled keyframe of other into this map as sub-map `submap`,
  // with ids shifted past this map's (offline merge of two saved runs). Returns the keyframe id
  // offset (new id = old id + offset); point ids are shifted too.
  KeyframeId append(const Map& other, int submap);
  // Erased keyframes -> (parent at the time, T_parent_kf).
  const std::map<KeyframeId, std::pair<KeyframeId, SE3>>& culled() const { return culled_; }

  const KeyFrame& keyframe(KeyframeId id) const { return keyframes_.at(id); }
  const MapPoint& point(PointId id) const { return points_.at(id); }
  bool has_keyframe(KeyframeId id) const { return keyframes_.count(id) > 0; }
  bool has_point(PointId id) const { return points_.count(id) > 0; }
  const std::map<KeyframeId, KeyFrame>& keyframes() const { return keyframes_; }
  const std::map<PointId, MapPoint>& points() const { return points_; }
  int n_keyframes() const { return static_cast<int>(keyframes_.size()); }
  int n_points() const { return static_cast<int>(points_.size()); }
  KeyframeId last_keyframe_id() const { return next_kf_id_ - 1; }

 private:
  friend class MapIo;  // map_io.cpp: a loaded map gets back its ids, culled chain and id counters
  std::map<KeyframeId, KeyFrame> keyframes_;
  std::map<PointId, MapPoint> points_;
  std::map<KeyframeId, std::pair<KeyframeId, SE3>> culled_;  // erased keyframe -> (parent, T_parent_kf)
  KeyframeId next_kf_id_ = 0;
  PointId next_point_id_ = 0;
};

// ORB scale level at which a point at distance dist_m is expected, given the distance range
// recorded for it (ORB-SLAM's scale prediction).
int predict_level(double dist_m, double max_dist_m, const features::ScalePyramid& pyr);

}  // namespace s3m::slam
