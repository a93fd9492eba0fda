#pragma once
// The simulator's ground-truth voxel map as a dense grid, for checking planned paths against the
// truth: exact distances to the nearest ground-truth voxel centre (separable squared EDT) and
// shortest 26-connected grid paths (multi-source Dijkstra) through the cells at least a robot
// radius from every voxel. Independent of the navigation module on purpose.
#include <algorithm>
#include <cmath>
#include <functional>
#include <limits>
#include <queue>
#include <vector>

#include <Eigen/Core>

#include "s3m/io/gt_voxels.hpp"

namespace s3m::it {

class GtGrid {
 public:
  GtGrid(const io::GtVoxelMap& gt, double pad_m) : res_(gt.resolution_m) {
    Eigen::Vector3d lo = Eigen::Vector3d::Constant(1e9), hi = -lo;
    for (const auto& c : gt.centres_w) lo = lo.cwiseMin(c.cast<double>()), hi = hi.cwiseMax(c.cast<double>());
    const int pad = int(std::ceil(pad_m / res_));
    origin_ = lo - Eigen::Vector3d::Constant(pad * res_);
    size_ = (((hi - lo) / res_).array().round().cast<int>() + 1 + 2 * pad).matrix();
    occupied_.assign(cells(), 0);
    for (const auto& c : gt.centres_w) occupied_[index(cell_of(c.cast<double>()))] = 1;
    labels_ = gt.labels;
    centres_ = gt.centres_w;
  }

  std::size_t cells() const { return std::size_t(size_.prod()); }
  Eigen::Vector3i cell(std::size_t i) const {
    return {int(i % size_.x()), int(i / size_.x() % size_.y()), int(i / size_.x() / size_.y())};
  }
  double res() const { return res_; }
  Eigen::Vector3i cell_of(const Eigen::Vector3d& p) const {
    return ((p - origin_) / res_).array().round().cast<int>();
  }
  Eigen::Vector3d centre(const Eigen::Vector3i& c) const { return origin_ + res_ * c.cast<double>(); }
  bool inside(const Eigen::Vector3i& c) const {
    return (c.array() >= 0).all() && (c.array() < size_.array()).all();
  }
  std::size_t index(const Eigen::Vector3i& c) const {
    return (std::size_t(c.z()) * size_.y() + c.y()) * size_.x() + c.x();
  }

  // Distance [m] from each cell centre to the nearest marked cell's centre (exact, squared EDT
  // one axis at a time, Felzenszwalb & Huttenlocher).
  std::vector<float> distance_to(const std::vector<std::uint8_t>& marked) const {
    const double inf = 1e20;
    std::vector<double> d(cells());
    for (std::size_t i = 0; i < cells(); ++i) d[i] = marked[i] ? 0.0 : inf;
    for (int axis = 0; axis < 3; ++axis) {
      const int n = size_[axis];
      std::vector<double> f(n), out(n);
      std::vector<int> v(n);
      std::vector<double> z(n + 1);
      const int a1 = (axis + 1) % 3, a2 = (axis + 2) % 3;
      for (int i = 0; i < size_[a1]; ++i)
        for (int j = 0; j < size_[a2]; ++j) {
          Eigen::Vector3i c;
          c[a1] = i, c[a2] = j;
          for (int k = 0; k < n; ++k) c[axis] = k, f[k] = d[index(c)];
          edt_1d(f, out, v, z);
          for (int k = 0; k < n; ++k) c[axis] = k, d[index(c)] = out[k];
        }
    }
    std::vector<float> dist(cells());
    for (std::size_t i = 0; i < cells(); ++i) dist[i] = float(std::sqrt(d[i]) * res_);
    return dist;
  }
  std::vector<float> distance_to_voxels() const { return distance_to(occupied_); }
  std::vector<float> distance_to_class(ClassId id) const {
    std::vector<std::uint8_t> m(cells(), 0);
    for (std::size_t i = 0; i < centres_.size(); ++i)
      if (labels_[i] == id) m[index(cell_of(centres_[i].cast<double>()))] = 1;
    return distance_to(m);
  }
  bool has_class(ClassId id) const { return std::find(labels_.begin(), labels_.end(), id) != labels_.end(); }

  // Exact distance [m] from p to the nearest ground-truth voxel centre, when below limit_m (else limit_m).
  double clearance(const Eigen::Vector3d& p, double limit_m) const {
    const Eigen::Vector3i c = cell_of(p);
    const int r = int(std::ceil(limit_m / res_)) + 1;
    double best = limit_m;
    for (int dz = -r; dz <= r; ++dz)
      for (int dy = -r; dy <= r; ++dy)
        for (int dx = -r; dx <= r; ++dx) {
          const Eigen::Vector3i q = c + Eigen::Vector3i(dx, dy, dz);
          if (inside(q) && occupied_[index(q)]) best = std::min(best, (centre(q) - p).norm());
        }
    return best;
  }

  // Shortest 26-connected path length [m] from every cell to the nearest goal cell, through cells
  // with free[i]; infinity where no goal is reachable.
  std::vector<float> path_lengths(const std::vector<std::uint8_t>& free,
                                  const std::vector<std::uint8_t>& goal) const {
    std::vector<float> g(cells(), std::numeric_limits<float>::infinity());
    using Item = std::pair<float, std::size_t>;
    std::priority_queue<Item, std::vector<Item>, std::greater<>> open;
    for (std::size_t i = 0; i < cells(); ++i)
      if (goal[i] && free[i]) g[i] = 0.0f, open.push({0.0f, i});
    while (!open.empty()) {
      const auto [d, i] = open.top();
      open.pop();
      if (d > g[i]) continue;
      const Eigen::Vector3i c = cell(i);
      for (int dz = -1; dz <= 1; ++dz)
        for (int dy = -1; dy <= 1; ++dy)
          for (int dx = -1; dx <= 1; ++dx) {
            const Eigen::Vector3i q = c + Eigen::Vector3i(dx, dy, dz);
            if ((dx | dy | dz) == 0 || !inside(q)) continue;
            const std::size_t j = index(q);
            const float nd = d + float(res_ * std::sqrt(double(dx * dx + dy * dy + dz * dz)));
            if (free[j] && nd < g[j]) g[j] = nd, open.push({nd, j});
          }
    }
    return g;
  }

 private:
  static void edt_1d(const std::vector<double>& f, std::vector<double>& d, std::vector<int>& v,
                     std::vector<double>& z) {
    const int n = int(f.size());
    int k = 0;
    v[0] = 0, z[0] = -1e30, z[1] = 1e30;
    const auto meet = [&](int q, int p) { return ((f[q] + q * q) - (f[p] + p * p)) / (2.0 * q - 2.0 * p); };
    for (int q = 1; q < n; ++q) {
      double s = meet(q, v[k]);
      while (s <= z[k]) s = meet(q, v[--k]);
      ++k, v[k] = q, z[k] = s, z[k + 1] = 1e30;
    }
    k = 0;
    for (int q = 0; q < n; ++q) {
      while (z[k + 1] < q) ++k;
      d[q] = double(q - v[k]) * (q - v[k]) + f[v[k]];
    }
  }

  double res_;
  Eigen::Vector3d origin_;
  Eigen::Vector3i size_;
  std::vector<std::uint8_t> occupied_;
  std::vector<ClassId> labels_;
  std::vector<Eigen::Vector3f> centres_;
};

}  // namespace s3m::it
