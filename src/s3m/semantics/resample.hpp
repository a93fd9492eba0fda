#pragma once
// Upsampling low-resolution class probabilities to the camera image, fused with top-k.
#include <vector>

#include <opencv2/core.hpp>

#include "s3m/semantics/label_map.hpp"

namespace s3m::semantics {

// Axis-aligned map from output (camera) pixels to plane coordinates: x = ax * u + bx, y = ay * v + by.
struct AxisMap {
  double ax = 1, bx = 0, ay = 1, by = 0;
};

// Top-k of the bilinearly interpolated planes at every pixel of an out_size image; coordinates are
// clamped to the plane (border replicated). Result is exactly what interpolating every plane to
// full size and then taking the top-k would give, but much cheaper: where the four plane cells
// around a pixel share the same ordered top-k list, interpolation preserves that order and no other
// class can overtake (each is below the k-th at every corner), so only the k probabilities are
// interpolated; all planes are evaluated only near label boundaries.
LabelMap resample_topk(const std::vector<cv::Mat>& planes, const std::vector<ClassId>& plane_ids, int k,
                       cv::Size out_size, const AxisMap& map);

// Copies each pixel of m into an s x s block and crops to out_size (nearest-neighbour upsampling).
LabelMap upsample_blocks(const LabelMap& m, int s, cv::Size out_size);

}  // namespace s3m::semantics
