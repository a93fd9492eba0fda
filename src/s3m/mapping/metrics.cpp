#include "s3m/mapping/metrics.hpp"

#include <cmath>
#include <sstream>
#include <unordered_map>

#include "s3m/mapping/voxelize.hpp"

namespace s3m::mapping {
namespace {

// Occupied finest voxels of the map: packed key -> top label (0 when unlabelled).
std::unordered_map<std::uint64_t, ClassId> occupied_voxels(const SemanticOcTree& tree) {
  std::unordered_map<std::uint64_t, ClassId> out;
  for (auto it = tree.begin_leafs(); it != tree.end_leafs(); ++it) {
    if (!tree.isNodeOccupied(*it)) continue;
    const int span = 1 << (tree.getTreeDepth() - it.getDepth());
    const octomap::OcTreeKey base = tree.adjustKeyAtDepth(it.getKey(), it.getDepth());
    for (int x = 0; x < span; ++x)
      for (int y = 0; y < span; ++y)
        for (int z = 0; z < span; ++z)
          out[pack_key(octomap::OcTreeKey(std::uint16_t(base[0] - span / 2 + x), std::uint16_t(base[1] - span / 2 + y),
                                          std::uint16_t(base[2] - span / 2 + z)))] = it->labels().top();
  }
  return out;
}

// The nearest (Chebyshev, then lexicographic offset order) key of `set` within tol of k.
template <typename Map>
const typename Map::value_type* nearest(const Map& set, const octomap::OcTreeKey& k, int tol) {
  for (int r = 0; r <= tol; ++r)
    for (int dz = -r; dz <= r; ++dz)
      for (int dy = -r; dy <= r; ++dy)
        for (int dx = -r; dx <= r; ++dx) {
          if (std::max({std::abs(dx), std::abs(dy), std::abs(dz)}) != r) continue;
          auto it = set.find(pack_key(octomap::OcTreeKey(std::uint16_t(k[0] + dx), std::uint16_t(k[1] + dy),
                                                         std::uint16_t(k[2] + dz))));
          if (it != set.end()) return &*it;
        }
  return nullptr;
}

}  // namespace

MapEvaluation evaluate_map(const SemanticOcTree& tree, const io::GtVoxelMap& gt, const MapEvalConfig& cfg) {
  MapEvaluation ev;
  const auto map = occupied_voxels(tree);
  // GT voxels re-keyed at the map resolution (several GT voxels may share a map cell).
  std::unordered_map<std::uint64_t, ClassId> gt_keys;
  for (std::size_t i = 0; i < gt.centres_w.size(); ++i) {
    const Eigen::Vector3f& c = gt.centres_w[i];
    gt_keys[pack_key(tree.coordToKey(c.x(), c.y(), c.z()))] = gt.labels[i];
  }
  ev.gt_voxels = gt_keys.size();
  ev.map_occupied_voxels = map.size();
  std::size_t tp_map = 0;
  for (const auto& [k, label] : map) {
    const octomap::OcTreeKey key(std::uint16_t(k & 0xffff), std::uint16_t((k >> 16) & 0xffff), std::uint16_t(k >> 32));
    tp_map += nearest(gt_keys, key, cfg.tolerance_voxels) != nullptr;
  }
  std::map<ClassId, std::size_t> inter, uni_gt, uni_map;
  std::size_t matched = 0, correct = 0, tp_gt = 0;
  for (const auto& [k, gt_label] : gt_keys) uni_gt[gt_label] += 0;  // every GT class is evaluated
  for (const auto& [k, gt_label] : gt_keys) {
    const octomap::OcTreeKey key(std::uint16_t(k & 0xffff), std::uint16_t((k >> 16) & 0xffff), std::uint16_t(k >> 32));
    const auto* m = nearest(map, key, cfg.tolerance_voxels);
    if (m == nullptr) continue;
    ++tp_gt, ++matched;
    const ClassId pred = m->second;
    ++uni_gt[gt_label], ++uni_map[pred];
    if (pred == gt_label) ++inter[gt_label], ++correct;
  }
  ev.precision = map.empty() ? 0.0 : double(tp_map) / double(map.size());
  ev.recall = gt_keys.empty() ? 0.0 : double(tp_gt) / double(gt_keys.size());
  ev.label_accuracy = matched ? double(correct) / double(matched) : 0.0;
  for (const auto& [c, n_gt] : uni_gt) {
    if (c == cls::kUnknown) continue;  // GT "unknown" is not evaluated
    const std::size_t i = inter[c], u = n_gt + uni_map[c] - i;
    ev.iou[c] = u ? double(i) / double(u) : 0.0;
  }
  for (const auto& [c, n_map] : uni_map)  // classes predicted but absent from GT: IoU 0
    if (c != cls::kUnknown && !ev.iou.count(c) && n_map > 0) ev.iou[c] = 0.0;
  double sum = 0.0, sum_observed = 0.0;
  std::size_t observed = 0;
  for (const auto& [c, v] : ev.iou) {
    sum += v;
    if (uni_gt[c] + uni_map[c] > 0) sum_observed += v, ++observed;
  }
  ev.miou = ev.iou.empty() ? 0.0 : sum / double(ev.iou.size());
  ev.miou_observed = observed ? sum_observed / double(observed) : 0.0;
  return ev;
}

MapSize map_size(const SemanticOcTree& tree, std::size_t raw_points, int k) {
  MapSize s;
  s.nodes = tree.size();
  s.leaves = tree.getNumLeafNodes();
  for (auto it = tree.begin_leafs(); it != tree.end_leafs(); ++it) s.occupied_leaves += tree.isNodeOccupied(*it);
  s.memory_bytes = tree.memoryUsage();
  std::ostringstream out;
  tree.write(out);
  s.file_bytes = out.str().size();
  s.raw_points = raw_points;
  s.raw_cloud_bytes = raw_points * (3 * sizeof(float) + 3 + std::size_t(k) * (sizeof(ClassId) + sizeof(float)));
  s.compression = s.file_bytes ? double(s.raw_cloud_bytes) / double(s.file_bytes) : 0.0;
  return s;
}

}  // namespace s3m::mapping
