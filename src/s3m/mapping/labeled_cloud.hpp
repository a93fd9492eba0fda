#pragma once
// One frame's labelled points plus the sensor origin, all in ONE frame that the holder states:
//  - the WORLD frame where the map takes them (Inserter::insert, voxelize);
//  - the CAMERA frame (origin 0) where the pipeline builds and keeps them (its KeyframeStore and
//    kept_clouds.bin), so that it can insert them again at corrected poses.
// Structure of arrays so the segmentation output converts without per-point objects.
#include <cstdint>
#include <vector>

#include <Eigen/Core>

#include "s3m/core/classes.hpp"

namespace s3m::mapping {

struct LabeledCloud {
  Eigen::Vector3f origin = Eigen::Vector3f::Zero();  // sensor (camera) centre, the cloud's frame [m]
  std::vector<Eigen::Vector3f> points;                // the cloud's frame [m]
  std::vector<std::uint8_t> rgb;                      // 3 per point (r, g, b) or empty: no colour
  int k = 0;                                          // labels per point, 0..kMaxLabels (0: none)
  std::vector<ClassId> labels;                        // k per point, point-major; any order
  std::vector<float> probs;                           // k per point, matching labels

  std::size_t size() const { return points.size(); }
  void reserve(std::size_t n);
  void shrink_to_fit();  // capacity = size (a cloud built by push_back holds up to 2x its points)
  // Appends a point; labels/probs must hold exactly k entries each (ignored when k == 0).
  void push_back(const Eigen::Vector3f& p, std::uint8_t r, std::uint8_t g, std::uint8_t b,
                 const ClassId* point_labels = nullptr, const float* point_probs = nullptr);
  void validate() const;  // throws s3m::Error when the array sizes disagree
};

}  // namespace s3m::mapping
