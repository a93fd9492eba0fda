#pragma once
// Guided matching against a keyframe's covisibility group: the map points of keyframe kf and its
// strongest covisible neighbours, predicted into a frame at a pose estimate and matched to its
// keypoints by descriptor near the predicted pixel. Loop verification and relocalisation both
// refine a RANSAC pose this way; they differ only in the parameters below.
#include <utility>
#include <vector>

#include "s3m/core/camera.hpp"
#include "s3m/features/frame_features.hpp"
#include "s3m/slam/map/map.hpp"

namespace s3m::slam {

struct GroupSearchParams {
  int group_size = 10;         // covisible neighbours of kf searched besides kf itself
  double radius_factor = 3.0;  // window = radius_factor * level scale [px]
  int levels_above = 0;        // a predicted level L matches keypoints of levels [L-1, L+levels_above]
  int max_distance = 50;       // Hamming
  double ratio = 0.9;          // best / second-best distance
  KeyframeId skip_observed_by = kNoId;  // leave out points this keyframe already observes
};

// (keypoint index in f, map point) pairs; every point and every keypoint appears at most once.
std::vector<std::pair<int, PointId>> match_covisible_group(const features::FrameFeatures& f, const Map& map,
                                                           KeyframeId kf, const SE3& T_w_c,
                                                           const PinholeCamera& camera,
                                                           const GroupSearchParams& params);

}  // namespace s3m::slam
