#pragma once
// Quadtree keypoint distribution (the ORB-SLAM idea): split the image region into quadrants
// until there are at least n_target nodes, then keep the strongest corner of every node.
// Keeps features spread over the image instead of clustered on the most textured object.
#include <vector>

#include <opencv2/core/types.hpp>

namespace s3m::features {

// Returns at most n_target keypoints from kps, all inside [x0,x1) x [y0,y1).
std::vector<cv::KeyPoint> distribute_quadtree(const std::vector<cv::KeyPoint>& kps, float x0, float x1,
                                              float y0, float y1, int n_target);

}  // namespace s3m::features
