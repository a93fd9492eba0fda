#pragma once
// Step 3 of the pipeline: a segmented RGB-D frame becomes a labelled point cloud. The cloud is a
// mapping::LabeledCloud expressed in the CAMERA frame (origin 0) while the pipeline keeps it, and is
// moved to the world frame only when it is inserted, so it can be re-inserted at corrected poses.
#include <cstddef>

#include <opencv2/core.hpp>

#include "s3m/core/camera.hpp"
#include "s3m/core/se3.hpp"
#include "s3m/mapping/labeled_cloud.hpp"
#include "s3m/semantics/label_map.hpp"

namespace s3m::pipeline {

struct BackprojectOptions {
  double min_depth_m = 0.2;  // range filter on the pixel's depth [m]
  double max_depth_m = 4.0;
  int pixel_stride = 1;      // every n-th pixel in u and v [px]
};

// Back-projects the pixels of depth_m (CV_32F, metres) whose depth is finite and within range,
// with their colour (bgr: CV_8UC3 or empty) and, when labels is non-empty, their top-k labels.
// Distortion is ignored: depth images are assumed to follow the pinhole model of `camera`.
mapping::LabeledCloud backproject(const PinholeCamera& camera, const cv::Mat& depth_m, const cv::Mat& bgr,
                                  const semantics::LabelMap& labels, const BackprojectOptions& options);

// Keeps one point per voxel of edge voxel_m (the first in scan order: deterministic, and every kept
// point is an actual measurement with its own labels). voxel_m <= 0 returns the input.
mapping::LabeledCloud voxel_downsample(const mapping::LabeledCloud& cloud, double voxel_m);

// The cloud moved by T_a_b (points and origin), e.g. camera frame -> world with T_w_c.
mapping::LabeledCloud transformed(const mapping::LabeledCloud& cloud_b, const SE3& T_a_b);

// Memory a cloud's arrays hold [bytes] (their capacity, not their size: what the kept-clouds budget
// is about; a 5,000-frame soak's kept clouds held 366 MB under a 256 MB budget counted by size).
std::size_t cloud_bytes(const mapping::LabeledCloud& cloud);


}  // namespace s3m::pipeline
