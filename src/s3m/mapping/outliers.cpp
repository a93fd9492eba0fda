#include "s3m/mapping/outliers.hpp"

#include <algorithm>
#include <cmath>

#include <tbb/parallel_for.h>

#include "s3m/mapping/insert.hpp"

namespace s3m::mapping {
namespace {

// Mean distance from voxel i's centroid to its `k` nearest occupied neighbour centroids within
// the 5x5x5 voxel block around it; +inf when it has no neighbour.
double mean_knn_distance(const VoxelSet& voxels, const std::vector<std::uint8_t>& state, std::size_t i, int k) {
  const Voxel& v = voxels.voxels[i];
  const Eigen::Vector3f c = v.centroid_w();
  std::array<float, 124> d{};
  int n = 0;
  for (int dz = -2; dz <= 2; ++dz)
    for (int dy = -2; dy <= 2; ++dy)
      for (int dx = -2; dx <= 2; ++dx) {
        if ((dx | dy | dz) == 0) continue;
        const octomap::OcTreeKey nk(std::uint16_t(v.key[0] + dx), std::uint16_t(v.key[1] + dy),
                                    std::uint16_t(v.key[2] + dz));
        const long j = voxels.index.find(pack_key(nk));
        if (j >= 0 && state[std::size_t(j)] == 0) d[n++] = (voxels.voxels[std::size_t(j)].centroid_w() - c).norm();
      }
  if (n == 0) return std::numeric_limits<double>::infinity();
  const int m = std::min(n, k);
  std::partial_sort(d.begin(), d.begin() + m, d.begin() + n);
  double sum = 0;
  for (int j = 0; j < m; ++j) sum += d[j];
  return sum / m;
}

}  // namespace

std::vector<bool> find_outliers(const VoxelSet& voxels, const std::vector<std::uint8_t>& state,
                                const BrickGrid& grid, const InsertConfig& cfg) {
  const std::size_t n = voxels.voxels.size();
  std::vector<char> drop(n, 0);
  std::vector<double> knn(cfg.sor_neighbors > 0 ? n : 0, 0.0);
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, n, 2048), [&](const auto& r) {
    for (std::size_t i = r.begin(); i < r.end(); ++i) {
      if (state[i] != 0) continue;
      const Voxel& v = voxels.voxels[i];
      if (int(v.count) < cfg.min_points_per_voxel) drop[i] = 1;
      if (cfg.radius_min_neighbors > 0 &&
          grid.occupied_neighbors(v.key, cfg.radius_min_neighbors) < cfg.radius_min_neighbors)
        drop[i] = 1;
      if (cfg.sor_neighbors > 0) knn[i] = mean_knn_distance(voxels, state, i, cfg.sor_neighbors);
    }
  });
  if (cfg.sor_neighbors > 0) {
    // Serial, fixed-order statistics so the threshold is bit-identical for any thread count.
    double sum = 0, sum_sq = 0;
    std::size_t m = 0;
    for (std::size_t i = 0; i < n; ++i)
      if (state[i] == 0 && std::isfinite(knn[i])) sum += knn[i], sum_sq += knn[i] * knn[i], ++m;
    const double mean = m ? sum / double(m) : 0.0;
    const double sd = m ? std::sqrt(std::max(0.0, sum_sq / double(m) - mean * mean)) : 0.0;
    const double limit = mean + cfg.sor_std_mul * sd;
    for (std::size_t i = 0; i < n; ++i)
      if (state[i] == 0 && !(knn[i] <= limit)) drop[i] = 1;
  }
  return std::vector<bool>(drop.begin(), drop.end());
}

}  // namespace s3m::mapping
