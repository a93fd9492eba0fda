#pragma once
// Descriptor matching for tracking and mapping: guided search around projected positions
// (with optional stereo-coordinate and rotation-consistency checks) and brute force with a
// ratio test.
#include <cstdint>
#include <utility>
#include <vector>

#include <opencv2/core.hpp>

#include "s3m/features/frame_features.hpp"

namespace s3m::features {

constexpr int kDescriptorBytes = 32;
constexpr int kMatchStrict = 50;   // max Hamming distance for matches without a geometric prior
constexpr int kMatchLoose = 100;   // max Hamming distance when the position is predicted

// Hamming distance of two 256-bit ORB descriptors.
int descriptor_distance(const std::uint8_t* a, const std::uint8_t* b);

// A 3D point (or a keypoint of another frame) predicted to appear in a frame.
struct ProjectionQuery {
  double u = 0, v = 0;        // predicted pixel [px]
  double u_right = kNoRight;  // predicted virtual right coordinate [px]; kNoRight: no check
  int min_level = 0, max_level = -1;  // keypoint levels allowed (max < 0: any)
  double radius_px = 10;      // search window half-size
  const std::uint8_t* descriptor = nullptr;
  float angle_deg = -1;       // orientation of the source keypoint; < 0: not used for rotation check
};

struct ProjectionMatchParams {
  int max_distance = kMatchLoose;
  double ratio = 0.8;              // best/second-best (same level) ratio; >= 1 disables
  bool check_orientation = false;  // keep only the dominant rotation-histogram bins
};

// Matches each query to one keypoint of f. Returns per query the keypoint index or -1. Keypoints
// with taken[i] != 0 are skipped; taken is set for the keypoints matched here. When two queries
// pick the same keypoint, the closer descriptor wins.
std::vector<int> match_by_projection(const FrameFeatures& f, const std::vector<ProjectionQuery>& queries,
                                     const ProjectionMatchParams& params, std::vector<char>& taken);

// Mutual-best brute-force matches (i in a, j in b) with Lowe's ratio test and a distance bound.
std::vector<std::pair<int, int>> match_brute_force(const cv::Mat& desc_a, const cv::Mat& desc_b,
                                                   int max_distance = kMatchStrict, double ratio = 0.8);

// Indices (into angle_diffs_deg) that fall in the up-to-three dominant bins of a 30-bin
// histogram of rotation differences; the second/third bin count only if >= 10 % of the first.
std::vector<int> rotation_consistent(const std::vector<float>& angle_diffs_deg);

}  // namespace s3m::features
