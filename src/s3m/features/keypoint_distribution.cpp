#include "s3m/features/keypoint_distribution.hpp"

#include <algorithm>
#include <cmath>

namespace s3m::features {
namespace {

struct Node {
  float x0, x1, y0, y1;
  std::vector<int> idx;
  bool can_split() const { return idx.size() > 1 && (x1 - x0) > 1.0f && (y1 - y0) > 1.0f; }
};

void split(const Node& n, const std::vector<cv::KeyPoint>& kps, std::vector<Node>& out) {
  const float xm = 0.5f * (n.x0 + n.x1), ym = 0.5f * (n.y0 + n.y1);
  Node c[4] = {{n.x0, xm, n.y0, ym, {}}, {xm, n.x1, n.y0, ym, {}}, {n.x0, xm, ym, n.y1, {}}, {xm, n.x1, ym, n.y1, {}}};
  for (int i : n.idx) {
    const auto& p = kps[i].pt;
    c[(p.x >= xm ? 1 : 0) + (p.y >= ym ? 2 : 0)].idx.push_back(i);
  }
  for (auto& ch : c)
    if (!ch.idx.empty()) out.push_back(std::move(ch));
}

}  // namespace

std::vector<cv::KeyPoint> distribute_quadtree(const std::vector<cv::KeyPoint>& kps, float x0, float x1,
                                              float y0, float y1, int n_target) {
  if (n_target <= 0 || kps.empty()) return {};
  // 1. Initial nodes: roughly square, side by side along the longer image axis.
  const int n_ini = std::max(1, static_cast<int>(std::lround((x1 - x0) / std::max(1.0f, y1 - y0))));
  const float w = (x1 - x0) / n_ini;
  std::vector<Node> nodes(n_ini);
  for (int i = 0; i < n_ini; ++i) nodes[i] = {x0 + i * w, x0 + (i + 1) * w, y0, y1, {}};
  for (int i = 0; i < static_cast<int>(kps.size()); ++i) {
    const auto& p = kps[i].pt;
    if (p.x < x0 || p.x >= x1 || p.y < y0 || p.y >= y1) continue;
    nodes[std::min(n_ini - 1, static_cast<int>((p.x - x0) / w))].idx.push_back(i);
  }
  nodes.erase(std::remove_if(nodes.begin(), nodes.end(), [](const Node& n) { return n.idx.empty(); }), nodes.end());

  // 2. Split the most populated nodes first until enough nodes exist or nothing can be split.
  while (static_cast<int>(nodes.size()) < n_target) {
    std::sort(nodes.begin(), nodes.end(), [](const Node& a, const Node& b) { return a.idx.size() > b.idx.size(); });
    if (!nodes.front().can_split()) break;
    std::vector<Node> next;
    next.reserve(nodes.size() * 2);
    std::size_t i = 0;
    for (; i < nodes.size() && static_cast<int>(next.size() + (nodes.size() - i)) < n_target; ++i) {
      if (nodes[i].can_split())
        split(nodes[i], kps, next);
      else
        next.push_back(std::move(nodes[i]));
    }
    for (; i < nodes.size(); ++i) next.push_back(std::move(nodes[i]));
    nodes.swap(next);
  }

  // 3. Strongest corner per node. Splitting can overshoot n_target; the surplus is taken from
  //    the smallest nodes (the densest areas) so the spread survives.
  std::sort(nodes.begin(), nodes.end(), [](const Node& a, const Node& b) {
    return (a.x1 - a.x0) * (a.y1 - a.y0) > (b.x1 - b.x0) * (b.y1 - b.y0);
  });
  if (static_cast<int>(nodes.size()) > n_target) nodes.resize(n_target);
  std::vector<cv::KeyPoint> out;
  out.reserve(nodes.size());
  for (const auto& n : nodes) {
    int best = n.idx.front();
    for (int i : n.idx)
      if (kps[i].response > kps[best].response) best = i;
    out.push_back(kps[best]);
  }
  return out;
}

}  // namespace s3m::features
