#pragma once
// Dense bitmap of one frame's touched voxels over the frame's bounding box, in 8^3 bricks laid
// out like FrameUpdate (see frame_update.hpp). Marks free voxels by ray casting (each distinct
// end voxel once, OctoMap's exact DDA), occupied voxels from the voxelized cloud, and emits the
// Morton-sorted FrameUpdate.
#include <cstddef>  // before OctoMap headers: OcTreeKey.h uses size_t unqualified
#include <cstdint>
#include <vector>

#include <octomap/OcTreeKey.h>
#include <octomap/octomap_types.h>

#include "s3m/mapping/frame_update.hpp"

namespace s3m::mapping {

// OctoMap's key <-> coordinate conversions for a 16-level tree of the given resolution.
struct KeyCoder {
  double res = 0.1, inv_res = 10.0;
  static constexpr int kMaxVal = 32768;
  explicit KeyCoder(double resolution_m) : res(resolution_m), inv_res(1.0 / resolution_m) {}
  bool key_checked(const octomap::point3d& p, octomap::OcTreeKey& key) const;
  double center(std::uint16_t k) const { return (double(int(k) - kMaxVal) + 0.5) * res; }
  octomap::point3d center(const octomap::OcTreeKey& k) const {
    return octomap::point3d(float(center(k[0])), float(center(k[1])), float(center(k[2])));
  }
};

class BrickGrid {
 public:
  // Covers the leaf keys in [lo, hi] (inclusive); clears all bits.
  void reset(const octomap::OcTreeKey& lo, const octomap::OcTreeKey& hi);

  bool contains(const octomap::OcTreeKey& k) const {
    return unsigned(k[0] - base_[0]) < extent_[0] && unsigned(k[1] - base_[1]) < extent_[1] &&
           unsigned(k[2] - base_[2]) < extent_[2];
  }
  void set_occupied(const octomap::OcTreeKey& k) { occ_[word(k)] |= mask(k); }
  void clear_occupied(const octomap::OcTreeKey& k) { occ_[word(k)] &= ~mask(k); }
  bool occupied(const octomap::OcTreeKey& k) const { return contains(k) && (occ_[word(k)] & mask(k)); }
  // Occupied voxels among the 26 neighbours of k, counting stops at `enough`.
  int occupied_neighbors(const octomap::OcTreeKey& k, int enough) const;

  // Marks the free voxels of rays from origin to each end point (OctoMap computeRayKeys
  // semantics: origin voxel included, end voxel excluded), in parallel; deterministic.
  void cast_rays(const KeyCoder& coder, const octomap::point3d& origin, const std::vector<octomap::point3d>& ends);

  // Emits every brick with a set bit into out.bricks, Morton-sorted; free bits of occupied
  // voxels are dropped (a hit wins, as in OctoMap). Does not touch out.observations.
  void build_bricks(FrameUpdate& out) const;

 private:
  // Per-axis lookup tables (key - base -> brick offset / in-brick bits): a voxel's word and bit
  // are three table lookups, which matters for millions of ray steps per frame.
  std::size_t word(const octomap::OcTreeKey& k) const {
    const std::size_t b = brick_off_[0][k[0] - base_[0]] + brick_off_[1][k[1] - base_[1]] + brick_off_[2][k[2] - base_[2]];
    const unsigned bit = bit_off_[0][k[0] - base_[0]] | bit_off_[1][k[1] - base_[1]] | bit_off_[2][k[2] - base_[2]];
    return b * 8 + (bit >> 6);
  }
  void mark(std::vector<std::uint64_t>& bits, int x, int y, int z) const {
    const unsigned ix = unsigned(x - base_[0]), iy = unsigned(y - base_[1]), iz = unsigned(z - base_[2]);
    if (ix >= extent_[0] || iy >= extent_[1] || iz >= extent_[2]) return;
    const unsigned bit = bit_off_[0][ix] | bit_off_[1][iy] | bit_off_[2][iz];
    bits[(brick_off_[0][ix] + brick_off_[1][iy] + brick_off_[2][iz]) * 8 + (bit >> 6)] |= 1ull << (bit & 63u);
  }
  std::uint64_t mask(const octomap::OcTreeKey& k) const {
    const unsigned bit = bit_off_[0][k[0] - base_[0]] | bit_off_[1][k[1] - base_[1]] | bit_off_[2][k[2] - base_[2]];
    return 1ull << (bit & 63u);
  }

  int base_[3] = {0, 0, 0};            // first key covered per axis (multiple of 8)
  unsigned extent_[3] = {0, 0, 0};     // keys covered per axis
  std::vector<std::size_t> brick_off_[3];
  std::vector<std::uint16_t> bit_off_[3];
  int lo_[3] = {0, 0, 0};  // brick coordinates of the first brick
  std::size_t nx_ = 0, ny_ = 0, nz_ = 0;
  std::vector<std::uint64_t> free_, occ_;  // 8 words per brick
  std::vector<std::vector<std::uint64_t>> free_parts_;  // per-task free bits, OR-ed afterwards
};

}  // namespace s3m::mapping
