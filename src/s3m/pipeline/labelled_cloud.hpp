#pragma once
// A keyframe's labelled point cloud in its camera frame: what the pipeline back-projects from a
// segmented RGB-D frame, keeps for re-integration after loop closures, and inserts into the map.
// Flat arrays (not per-point structs with fixed label slots) keep a kept keyframe small.
#include <cstdint>
#include <vector>

#include <Eigen/Core>
#include <opencv2/core.hpp>

#include "s3m/core/camera.hpp"
#include "s3m/core/classes.hpp"
#include "s3m/semantics/label_map.hpp"

namespace s3m::pipeline {

struct LabelledCloud {
  int k = 0;                                   // labels per point (0 = no semantics)
  std::vector<Eigen::Vector3f> p_c;            // points in the camera frame [m]
  std::vector<std::uint8_t> bgr;               // 3 bytes per point (OpenCV order)
  std::vector<ClassId> ids;                    // k per point, most probable first; 0 = none
  std::vector<float> probs;                    // k per point, matching ids, in [0, 1]

  std::size_t size() const { return p_c.size(); }
  std::size_t bytes() const;  // memory held, for the "kept keyframes" statistic
};

struct BackprojectOptions {
  double min_depth_m = 0.2;  // range filter [m]
  double max_depth_m = 4.0;
  int pixel_stride = 1;      // every n-th pixel in u and v [px]
};

// Back-projects the pixels of depth_m (CV_32F, metres) whose depth is finite and within range,
// with their colour and (when labels is non-empty) their top-k labels. Distortion is ignored:
// the depth image is assumed to follow the pinhole model of `camera` (as the datasets provide it).
LabelledCloud backproject(const PinholeCamera& camera, const cv::Mat& depth_m, const cv::Mat& bgr,
                          const semantics::LabelMap& labels, const BackprojectOptions& options);

// Keeps one point per voxel of edge voxel_m (the first in scan order, so the result is
// deterministic and each kept point is an actual measurement with its own labels).
LabelledCloud voxel_downsample(const LabelledCloud& cloud, double voxel_m);

// Raw bytes of a point cloud with position, colour and one label per point (x y z float, rgb,
// label u16, confidence float = 21 B): the reference for the "map is N x smaller" statistic.
constexpr std::size_t kRawPointBytes = 3 * 4 + 3 + 2 + 4;

}  // namespace s3m::pipeline
