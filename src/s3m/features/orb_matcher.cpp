#include "s3m/features/orb_matcher.hpp"

#include <algorithm>
#include <array>
#include <bit>
#include <cmath>
#include <cstring>
#include <limits>

#include <opencv2/features2d.hpp>

namespace s3m::features {

int descriptor_distance(const std::uint8_t* a, const std::uint8_t* b) {
  int d = 0;
  for (int k = 0; k < kDescriptorBytes; k += 8) {
    std::uint64_t x, y;
    std::memcpy(&x, a + k, 8);
    std::memcpy(&y, b + k, 8);
    d += std::popcount(x ^ y);
  }
  return d;
}

std::vector<int> rotation_consistent(const std::vector<float>& diffs) {
  constexpr int kBins = 30;
  std::array<std::vector<int>, kBins> hist;
  for (int i = 0; i < static_cast<int>(diffs.size()); ++i) {
    float d = std::fmod(diffs[i], 360.0f);
    if (d < 0) d += 360.0f;
    hist[std::min(kBins - 1, static_cast<int>(d * kBins / 360.0f))].push_back(i);
  }
  std::array<int, kBins> order;
  for (int b = 0; b < kBins; ++b) order[b] = b;
  std::partial_sort(order.begin(), order.begin() + 3, order.end(),
                    [&](int a, int b) { return hist[a].size() > hist[b].size(); });
  std::vector<int> keep = hist[order[0]];
  for (int k = 1; k < 3; ++k)
    if (hist[order[k]].size() >= 0.1 * hist[order[0]].size() && !hist[order[k]].empty())
      keep.insert(keep.end(), hist[order[k]].begin(), hist[order[k]].end());
  return keep;
}

std::vector<int> match_by_projection(const FrameFeatures& f, const std::vector<ProjectionQuery>& queries,
                                     const ProjectionMatchParams& params, std::vector<char>& taken) {
  const int nq = static_cast<int>(queries.size());
  std::vector<int> match(nq, -1);
  std::vector<int> owner(f.size(), -1);     // query currently holding keypoint i
  std::vector<int> owner_dist(f.size(), std::numeric_limits<int>::max());
  std::vector<int> best_dist(nq, 0);
  // 1. Best keypoint per query inside its window.
  for (int q = 0; q < nq; ++q) {
    const auto& Q = queries[q];
    int best = std::numeric_limits<int>::max(), second = best, best_idx = -1, best_level = -1, second_level = -1;
    for (int i : f.in_area(Q.u, Q.v, Q.radius_px, Q.min_level, Q.max_level)) {
      if (taken[i]) continue;
      if (has_right(Q.u_right) && has_right(f.u_right[i]) && std::abs(Q.u_right - f.u_right[i]) > Q.radius_px) continue;
      const int d = descriptor_distance(Q.descriptor, f.descriptor(i));
      if (d < best) {
        second = best;
        second_level = best_level;
        best = d;
        best_idx = i;
        best_level = f.keypoints[i].octave;
      } else if (d < second) {
        second = d;
        second_level = f.keypoints[i].octave;
      }
    }
    if (best_idx < 0 || best > params.max_distance) continue;
    if (params.ratio < 1.0 && best_level == second_level && best > params.ratio * second) continue;
    // 2. One query per keypoint: the closer descriptor wins.
    if (best < owner_dist[best_idx]) {
      if (owner[best_idx] >= 0) match[owner[best_idx]] = -1;
      owner[best_idx] = q;
      owner_dist[best_idx] = best;
      match[q] = best_idx;
      best_dist[q] = best;
    }
  }
  // 3. Rotation consistency over the matches whose source orientation is known.
  if (params.check_orientation) {
    std::vector<int> qs;
    std::vector<float> diffs;
    for (int q = 0; q < nq; ++q)
      if (match[q] >= 0 && queries[q].angle_deg >= 0) {
        qs.push_back(q);
        diffs.push_back(f.keypoints[match[q]].angle - queries[q].angle_deg);
      }
    std::vector<char> ok(qs.size(), 0);
    for (int k : rotation_consistent(diffs)) ok[k] = 1;
    for (std::size_t k = 0; k < qs.size(); ++k)
      if (!ok[k]) match[qs[k]] = -1;
  }
  for (int q = 0; q < nq; ++q)
    if (match[q] >= 0) taken[match[q]] = 1;
  return match;
}

std::vector<std::pair<int, int>> match_brute_force(const cv::Mat& desc_a, const cv::Mat& desc_b, int max_distance,
                                                   double ratio) {
  std::vector<std::pair<int, int>> out;
  if (desc_a.empty() || desc_b.rows < 2) return out;
  cv::BFMatcher matcher(cv::NORM_HAMMING);
  std::vector<std::vector<cv::DMatch>> knn;
  matcher.knnMatch(desc_a, desc_b, knn, 2);
  std::vector<int> best_a_for_b(desc_b.rows, -1);
  std::vector<float> best_d_for_b(desc_b.rows, std::numeric_limits<float>::max());
  for (const auto& m : knn) {
    if (m.size() < 2 || m[0].distance > max_distance || m[0].distance > ratio * m[1].distance) continue;
    if (m[0].distance < best_d_for_b[m[0].trainIdx]) {
      best_d_for_b[m[0].trainIdx] = m[0].distance;
      best_a_for_b[m[0].trainIdx] = m[0].queryIdx;
    }
  }
  for (int j = 0; j < desc_b.rows; ++j)
    if (best_a_for_b[j] >= 0) out.emplace_back(best_a_for_b[j], j);
  std::sort(out.begin(), out.end());
  return out;
}

}  // namespace s3m::features
