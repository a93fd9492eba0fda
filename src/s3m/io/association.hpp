#pragma once
// Timestamp association as in TUM RGB-D's associate.py: every pair (a_i, b_j) with
// |a_i - (b_j + offset_s)| < max_dt_s is a candidate; candidates are taken greedily in order of
// increasing time difference, each index used at most once. Result sorted by a index.
// Unlike associate.py this is O((n + m) log) for sorted inputs: only b's inside the window are visited.
#include <cstddef>
#include <utility>
#include <vector>

namespace s3m::io {

struct Match {
  std::size_t a = 0, b = 0;
  double dt_s = 0.0;  // a_t - (b_t + offset)
};

// a and b must be sorted ascending (trajectories and TUM lists are); throws s3m::Error otherwise.
std::vector<Match> associate(const std::vector<double>& a_s, const std::vector<double>& b_s,
                             double max_dt_s = 0.02, double offset_s = 0.0);

// Index of the element of sorted ts closest to t (ties -> earlier); ts must be non-empty.
std::size_t closest_index(const std::vector<double>& ts, double t);

// Colour/depth pairing of recorded streams (ROS bags, ROS 2 recordings), all stamps sorted: each
// colour stamp takes the depth stamp closest to it within max_dt_s unless an earlier colour image
// took it (a depth image is used once); a colour image without one is skipped and counted. Label
// stamps (may be empty) are matched the same way, not exclusively; labels -1: none within max_dt_s.
struct StampPair {
  std::size_t rgb = 0, depth = 0;
  long labels = -1;
};
struct StampPairs {
  std::vector<StampPair> pairs;
  std::size_t skipped = 0;  // colour images without a depth image
};
StampPairs pair_by_stamp(const std::vector<double>& rgb_s, const std::vector<double>& depth_s,
                         const std::vector<double>& labels_s, double max_dt_s);

}  // namespace s3m::io
