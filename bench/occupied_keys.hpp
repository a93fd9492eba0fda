#pragma once
// Shared by the mapping benchmarks: the set of occupied finest-level voxel keys of any OctoMap tree
// (ours or stock), expanding pruned occupied inner nodes, so two maps can be compared voxel by voxel.
#include <cstdint>
#include <set>

#include <octomap/OcTreeKey.h>

#include "s3m/mapping/voxelize.hpp"

namespace s3m::bench {

template <typename Tree>
std::set<std::uint64_t> occupied_keys(const Tree& tree) {
  std::set<std::uint64_t> out;
  for (auto it = tree.begin_leafs(); it != tree.end_leafs(); ++it) {
    if (!tree.isNodeOccupied(*it)) continue;
    const int span = 1 << (tree.getTreeDepth() - it.getDepth());
    const octomap::OcTreeKey base = tree.coordToKey(it.getCoordinate(), it.getDepth());
    for (int x = 0; x < span; ++x)
      for (int y = 0; y < span; ++y)
        for (int z = 0; z < span; ++z)
          out.insert(mapping::pack_key(
              octomap::OcTreeKey(base[0] - span / 2 + x, base[1] - span / 2 + y, base[2] - span / 2 + z)));
  }
  return out;
}

}  // namespace s3m::bench
