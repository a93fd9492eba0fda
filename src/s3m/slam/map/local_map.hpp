#pragma once
// Messages between tracking and local mapping. The tracker never touches the Map: it sends a
// KeyFrameRequest and receives LocalMapSnapshot copies of the map around the newest keyframe.
#include <map>
#include <memory>
#include <unordered_map>
#include <vector>

#include "s3m/core/rgbd_frame.hpp"
#include "s3m/core/se3.hpp"
#include "s3m/features/frame_features.hpp"
#include "s3m/slam/map/map.hpp"
#include "s3m/slam/map/types.hpp"

namespace s3m::slam {

struct PointVisibility {
  PointId id = kNoId;
  int n_visible = 0;  // times the point was predicted inside a tracked frame
  int n_found = 0;    // times it was matched and an inlier
};

struct KeyFrameRequest {
  int frame_index = 0;
  double t_s = 0;
  SE3 T_w_c = SE3::Identity();
  std::shared_ptr<const features::FrameFeatures> features;
  std::vector<PointId> points;              // per keypoint: tracked inlier map point or kNoId
  std::vector<PointVisibility> visibility;  // tracking statistics since the previous request
  int submap = 0;  // the sub-map tracking was in (T_w_c is in its frame; Map::KeyFrame::submap)
  // The first keyframe of a map: every keypoint with depth becomes a point, not only the close ones
  // (ORB-SLAM's RGB-D initialisation). A first view of far walls (3-4 m) otherwise leaves the next
  // frames ~100 points to track, too few to hold on (see docs/DECISIONS.md, "Keyframe policy").
  bool first_of_map = false;
  // Deep copies of the frame's colour and depth for the dense link to the previous keyframe
  // (MapperConfig::dense_links, keyframe_links.hpp); empty when those are off.
  RgbdFrame image;
};

struct SnapshotPoint {
  PointId id = kNoId;
  Vec3 p_w = Vec3::Zero();
  Descriptor descriptor{};
  Vec3 normal_w = Vec3::UnitZ();
  double min_dist_m = 0, max_dist_m = 0;
};

struct SnapshotKeyFrame {
  KeyframeId id = kNoId;
  SE3 T_w_c = SE3::Identity();
  std::shared_ptr<const features::FrameFeatures> features;
  std::vector<PointId> points;
};

struct LocalMapSnapshot {
  KeyframeId reference_kf = kNoId;          // the newest keyframe; keyframes[0]
  std::vector<SnapshotKeyFrame> keyframes;  // reference first, then its covisibility window
  std::vector<SnapshotPoint> points;        // every point those keyframes observe
  std::unordered_map<PointId, int> point_index;
  int submap = 0;           // the reference keyframe's sub-map
  int n_map_keyframes = 0;  // keyframes of that sub-map
  // Sub-maps merged so far: merged -> (the sub-map it joined, T_into_from). A tracker still in a
  // merged sub-map's frame follows the chain to this snapshot's (Tracker::set_snapshot).
  std::map<int, std::pair<int, SE3>> merged_into;
  int ref_tracked_points = 0;  // reference keyframe points with enough observations (keyframe rule)

  const SnapshotPoint* find(PointId id) const {
    const auto it = point_index.find(id);
    return it == point_index.end() ? nullptr : &points[it->second];
  }
};

// Copies the map around keyframe ref: ref, its best covisible keyframes and their neighbours, up
// to max_keyframes, with all their points.
LocalMapSnapshot make_snapshot(const Map& map, KeyframeId ref, int max_keyframes);

// The keyframe observing most of points (ties: the smaller id); kNoId when none does. ORB-SLAM's
// choice of the reference keyframe for a frame's local map.
KeyframeId best_covisible_keyframe(const Map& map, const std::vector<PointId>& points);

}  // namespace s3m::slam
