#pragma once
// Which keypoints become points from their own depth, ORB-SLAM's rule for RGB-D keyframes, shared
// by local mapping (a keyframe's new map points), the tracker's view of a keyframe still being
// mapped, and the tracker's visual-odometry points for the next frame.
#include <algorithm>
#include <utility>
#include <vector>

#include "s3m/features/frame_features.hpp"

namespace s3m::slam {

// Every keypoint with depth for which is_free(i) holds and whose depth is at most close_depth_m,
// and beyond that the closest ones until there are min_points in all. (depth [m], keypoint index)
// pairs, closest first.
template <class IsFree>
std::vector<std::pair<float, int>> depth_point_keypoints(const features::FrameFeatures& f, IsFree is_free,
                                                         double close_depth_m, int min_points) {
  std::vector<std::pair<float, int>> by_depth;
  for (int i = 0; i < f.size(); ++i)
    if (f.has_depth(i) && is_free(i)) by_depth.emplace_back(f.depth_m[i], i);
  std::sort(by_depth.begin(), by_depth.end());
  std::size_t n = 0;
  while (n < by_depth.size() && (by_depth[n].first <= close_depth_m || static_cast<int>(n) < min_points)) ++n;
  by_depth.resize(n);
  return by_depth;
}

}  // namespace s3m::slam
