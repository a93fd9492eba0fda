#include "s3m/navigation/reachability.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <functional>
#include <limits>
#include <queue>
#include <unordered_map>

namespace s3m::navigation {

Reachability grid_reachability(const DistanceField& field, const Eigen::Vector3d& start_w,
                               const std::vector<Eigen::Vector3d>& points_w, double required_m) {
  const double res = field.resolution();
  const Eigen::Vector3i size = ((field.max_w() - field.min_w()) / res).array().round().cast<int>() + 1;
  const auto cell_of = [&](const Eigen::Vector3d& p) -> Eigen::Vector3i {
    return ((p - field.min_w()) / res).array().round().cast<int>();
  };
  const auto inside = [&](const Eigen::Vector3i& c) {
    return (c.array() >= 0).all() && (c.array() < size.array()).all();
  };
  const auto index = [&](const Eigen::Vector3i& c) {
    return (std::size_t(c.z()) * size.y() + c.y()) * size.x() + c.x();
  };
  Reachability out;
  out.lengths_m.assign(points_w.size(), std::numeric_limits<double>::infinity());
  out.paths_w.resize(points_w.size());
  const Eigen::Vector3i start = cell_of(start_w);
  if (!inside(start)) return out;
  // Points waiting to be settled, by voxel.
  std::unordered_map<std::size_t, std::vector<std::size_t>> waiting;
  for (std::size_t i = 0; i < points_w.size(); ++i)
    if (const auto c = cell_of(points_w[i]); inside(c)) waiting[index(c)].push_back(i);
  // 0 = not looked at, 1 = free enough, 2 = blocked; distances only for voxels reached.
  std::vector<std::uint8_t> state(std::size_t(size.prod()), 0);
  std::vector<float> dist(state.size(), std::numeric_limits<float>::infinity());
  std::vector<std::uint32_t> parent(state.size(), 0);
  const auto passable = [&](const Eigen::Vector3i& c, std::size_t i) {
    if (state[i] == 0)
      state[i] = field.clearance(field.min_w() + res * c.cast<double>()) >= required_m ? 1 : 2;
    return state[i] == 1;
  };
  using Item = std::pair<float, std::size_t>;
  std::priority_queue<Item, std::vector<Item>, std::greater<>> open;
  dist[index(start)] = 0.0f;
  open.push({0.0f, index(start)});
  while (!open.empty() && !waiting.empty()) {
    const auto [d, i] = open.top();
    open.pop();
    if (d > dist[i]) continue;
    ++out.voxels_reached;
    if (const auto it = waiting.find(i); it != waiting.end()) {
      std::vector<Eigen::Vector3d> path;
      for (std::size_t k = i;; k = parent[k]) {
        const Eigen::Vector3i ck(int(k % size.x()), int(k / size.x() % size.y()),
                                 int(k / size.x() / size.y()));
        path.push_back(field.min_w() + res * ck.cast<double>());
        if (k == index(start)) break;
      }
      std::reverse(path.begin(), path.end());
      for (const std::size_t p : it->second) out.lengths_m[p] = d, out.paths_w[p] = path;
      waiting.erase(it);
    }
    const Eigen::Vector3i c(int(i % size.x()), int(i / size.x() % size.y()), int(i / size.x() / size.y()));
    for (int dz = -1; dz <= 1; ++dz)
      for (int dy = -1; dy <= 1; ++dy)
        for (int dx = -1; dx <= 1; ++dx) {
          const Eigen::Vector3i q = c + Eigen::Vector3i(dx, dy, dz);
          if ((dx | dy | dz) == 0 || !inside(q)) continue;
          const std::size_t j = index(q);
          const float nd = d + float(res * std::sqrt(double(dx * dx + dy * dy + dz * dz)));
          if (nd < dist[j] && passable(q, j)) dist[j] = nd, parent[j] = std::uint32_t(i), open.push({nd, j});
        }
  }
  return out;
}

}  // namespace s3m::navigation
