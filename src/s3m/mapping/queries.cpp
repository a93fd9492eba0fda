#include "s3m/mapping/queries.hpp"

#include <algorithm>
#include <unordered_map>

#include "s3m/mapping/voxelize.hpp"

namespace s3m::mapping {
namespace {

VoxelInfo info_of(const SemanticOcTree& tree, const SemanticOcTreeNode& n, const octomap::point3d& c, double size) {
  VoxelInfo v;
  v.center_w = Eigen::Vector3d(c.x(), c.y(), c.z());
  v.size_m = size;
  v.label = n.labels().top();
  v.confidence = n.labels().top_prob();
  v.occupancy = n.getOccupancy();
  (void)tree;
  return v;
}

bool counts(const SemanticOcTree& tree, const SemanticOcTreeNode& n) {
  return tree.isNodeOccupied(n) && !n.labels().empty();
}

// Finest keys of a leaf at `depth` (pruned leaves cover 8^(16-depth) voxels).
template <typename F>
void for_each_finest_key(const SemanticOcTree& tree, const octomap::OcTreeKey& key, unsigned depth, F&& f) {
  const int span = 1 << (tree.getTreeDepth() - depth);
  const octomap::OcTreeKey base = tree.adjustKeyAtDepth(key, depth);
  const int half = span / 2;
  for (int x = 0; x < span; ++x)
    for (int y = 0; y < span; ++y)
      for (int z = 0; z < span; ++z)
        f(octomap::OcTreeKey(std::uint16_t(base[0] - half + x), std::uint16_t(base[1] - half + y),
                             std::uint16_t(base[2] - half + z)));
}

}  // namespace

std::optional<VoxelInfo> class_at(const SemanticOcTree& tree, const Eigen::Vector3d& p_w) {
  octomap::OcTreeKey key;
  if (!tree.coordToKeyChecked(p_w.x(), p_w.y(), p_w.z(), key)) return std::nullopt;
  // Walk down to the leaf holding key (possibly a pruned, larger node) to know its size.
  const SemanticOcTreeNode* n = tree.getRoot();
  unsigned depth = 0;
  const unsigned max_depth = tree.getTreeDepth();
  while (n != nullptr && depth < max_depth && tree.nodeHasChildren(n)) {
    const unsigned i = octomap::computeChildIdx(key, int(max_depth - 1 - depth));
    n = tree.nodeChildExists(n, i) ? tree.getNodeChild(n, i) : nullptr;
    ++depth;
  }
  if (n == nullptr || !counts(tree, *n)) return std::nullopt;
  return info_of(tree, *n, tree.keyToCoord(key, depth), tree.getNodeSize(depth));
}

std::vector<VoxelInfo> voxels_of_class(const SemanticOcTree& tree, ClassId label) {
  std::vector<VoxelInfo> out;
  for (auto it = tree.begin_leafs(); it != tree.end_leafs(); ++it)
    if (counts(tree, *it) && it->labels().top() == label)
      out.push_back(info_of(tree, *it, it.getCoordinate(), it.getSize()));
  return out;
}

std::vector<std::size_t> class_voxel_counts(const SemanticOcTree& tree) {
  std::vector<std::size_t> n;
  const unsigned max_depth = tree.getTreeDepth();
  for (auto it = tree.begin_leafs(); it != tree.end_leafs(); ++it) {
    if (!counts(tree, *it)) continue;
    const ClassId id = it->labels().top();
    if (n.size() <= id) n.resize(std::size_t(id) + 1, 0);
    n[id] += std::size_t{1} << (3 * (max_depth - it.getDepth()));  // a pruned leaf covers 8^d voxels
  }
  return n;
}

std::vector<ObjectInstance> object_instances(const SemanticOcTree& tree, ClassId label, std::size_t min_voxels) {
  // 1. The class's finest voxels with their confidence, in sorted key order (deterministic seeds).
  std::unordered_map<std::uint64_t, float> conf;
  std::vector<std::uint64_t> keys;
  for (auto it = tree.begin_leafs(); it != tree.end_leafs(); ++it) {
    if (!counts(tree, *it) || it->labels().top() != label) continue;
    for_each_finest_key(tree, it.getKey(), it.getDepth(), [&](const octomap::OcTreeKey& k) {
      keys.push_back(pack_key(k));
      conf[pack_key(k)] = it->labels().top_prob();
    });
  }
  std::sort(keys.begin(), keys.end());
  // 2. Flood fill over the 26-neighbourhood.
  std::unordered_map<std::uint64_t, bool> seen;
  std::vector<ObjectInstance> out;
  const double res = tree.getResolution();
  for (std::uint64_t seed : keys) {
    if (seen[seed]) continue;
    ObjectInstance inst;
    inst.label = label;
    inst.bbox_min_w.setConstant(1e300);
    inst.bbox_max_w.setConstant(-1e300);
    std::vector<std::uint64_t> stack{seed};
    seen[seed] = true;
    while (!stack.empty()) {
      const std::uint64_t k = stack.back();
      stack.pop_back();
      const octomap::OcTreeKey key(std::uint16_t(k & 0xffff), std::uint16_t((k >> 16) & 0xffff), std::uint16_t(k >> 32));
      const octomap::point3d c = tree.keyToCoord(key);
      const Eigen::Vector3d cw(c.x(), c.y(), c.z());
      ++inst.voxels;
      inst.centroid_w += cw;
      inst.bbox_min_w = inst.bbox_min_w.cwiseMin(cw - Eigen::Vector3d::Constant(res / 2));
      inst.bbox_max_w = inst.bbox_max_w.cwiseMax(cw + Eigen::Vector3d::Constant(res / 2));
      inst.mean_confidence += conf[k];
      for (int dz = -1; dz <= 1; ++dz)
        for (int dy = -1; dy <= 1; ++dy)
          for (int dx = -1; dx <= 1; ++dx) {
            const std::uint64_t n = pack_key(octomap::OcTreeKey(std::uint16_t(key[0] + dx), std::uint16_t(key[1] + dy),
                                                                std::uint16_t(key[2] + dz)));
            if (conf.count(n) && !seen[n]) seen[n] = true, stack.push_back(n);
          }
    }
    if (inst.voxels < min_voxels) continue;
    inst.centroid_w /= double(inst.voxels);
    inst.mean_confidence /= double(inst.voxels);
    inst.volume_m3 = double(inst.voxels) * res * res * res;
    out.push_back(inst);
  }
  std::sort(out.begin(), out.end(), [](const ObjectInstance& a, const ObjectInstance& b) {
    if (a.voxels != b.voxels) return a.voxels > b.voxels;
    return std::lexicographical_compare(a.centroid_w.data(), a.centroid_w.data() + 3, b.centroid_w.data(),
                                        b.centroid_w.data() + 3);
  });
  return out;
}

}  // namespace s3m::mapping
