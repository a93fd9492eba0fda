#pragma once
// One frame's change to the map, prepared by the Inserter and applied by
// SemanticOcTree::applyFrameUpdate in a single pass.
//
// Voxels are grouped in "bricks" of 8x8x8 leaves: exactly the subtree below one depth-13 node of
// OctoMap's 16-level tree. Inside a brick, bit b = (c14 << 6) | (c15 << 3) | c16 where cD is the
// OctoMap child index at depth D, so every subtree is a contiguous bit range and the bits are in
// the tree's depth-first order. Bricks are sorted by the Morton code of their key (key >> 3),
// which is also depth-first order, so the update walks the tree once, top down.
#include <cstddef>  // before OctoMap headers: OcTreeKey.h uses size_t unqualified
#include <array>
#include <cstdint>
#include <vector>

#include <octomap/OcTreeKey.h>

#include "s3m/mapping/label_set.hpp"
#include "s3m/mapping/semantic_octree.hpp"

namespace s3m::mapping {

inline constexpr unsigned kBrickDepth = 13;  // depth of the node that owns a brick (16 - 3)

struct VoxelObservation {
  LabelSet labels;  // merged labels of the points in the voxel, top-k
  Rgb color;
  bool has_color = false;
};

struct BrickUpdate {
  std::uint64_t morton = 0;                    // Morton code of the brick key (key >> 3)
  std::array<std::uint64_t, 8> free{};         // leaves to integrate a miss into
  std::array<std::uint64_t, 8> occupied{};     // leaves to integrate a hit + observation into
  std::uint32_t first_obs = 0;                 // index of the first observation of this brick
};

struct FrameUpdate {
  std::vector<BrickUpdate> bricks;             // sorted by morton, unique
  std::vector<VoxelObservation> observations;  // one per occupied bit, in brick then bit order
};

// In-brick bit of a leaf key (see the file comment).
inline unsigned brick_bit(const octomap::OcTreeKey& key) {
  auto child = [&](unsigned bit) {
    return ((key[0] >> bit) & 1u) | (((key[1] >> bit) & 1u) << 1) | (((key[2] >> bit) & 1u) << 2);
  };
  return (child(2) << 6) | (child(1) << 3) | child(0);
}

// Morton code of a brick key (13 bits per axis); the top 3 bits are the root's child index.
inline std::uint64_t brick_morton(unsigned bx, unsigned by, unsigned bz) {
  std::uint64_t m = 0;
  for (int bit = 12; bit >= 0; --bit)
    m = (m << 3) | ((bx >> bit) & 1u) | (((by >> bit) & 1u) << 1) | (((bz >> bit) & 1u) << 2);
  return m;
}

// OctoMap child index, at depth d (0..12, the node's depth), of the path to a brick.
inline unsigned brick_child_at(std::uint64_t morton, unsigned depth) {
  return unsigned(morton >> (3 * (kBrickDepth - 1 - depth))) & 7u;
}

}  // namespace s3m::mapping
