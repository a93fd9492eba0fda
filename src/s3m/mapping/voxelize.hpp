#pragma once
// Step 1 of insertion: group a frame's points by map voxel (down-sampling at map resolution).
// Each voxel keeps its point count, centroid, mean colour and the merged labels of its points
// (per-label mean probability over the points, then top-k), i.e. one observation per voxel.
#include <cstddef>  // before OctoMap headers: OcTreeKey.h uses size_t unqualified
#include <cstdint>
#include <vector>

#include <octomap/OcTreeKey.h>

#include "s3m/mapping/frame_update.hpp"
#include "s3m/mapping/labeled_cloud.hpp"

namespace s3m::mapping {

// Packs a leaf key into 48 bits (x | y << 16 | z << 32).
inline std::uint64_t pack_key(const octomap::OcTreeKey& k) {
  return std::uint64_t(k[0]) | (std::uint64_t(k[1]) << 16) | (std::uint64_t(k[2]) << 32);
}

// Open-addressing hash map from packed keys to indices; grows as needed, keeps its capacity
// across frames so steady-state insertion does not allocate.
class KeyIndexMap {
 public:
  void clear(std::size_t expected);
  // Index stored for key, or `next` after inserting it (inserted = true).
  std::uint32_t find_or_insert(std::uint64_t key, std::uint32_t next, bool& inserted);
  long find(std::uint64_t key) const;  // -1 when absent

 private:
  void grow();
  static constexpr std::uint64_t kEmpty = ~0ull;
  std::vector<std::uint64_t> keys_;
  std::vector<std::uint32_t> vals_;
  std::size_t size_ = 0;
  int shift_ = 64;
};

struct Voxel {
  static constexpr int kSlots = 2 * kMaxLabels;  // distinct labels merged per voxel (more: dropped)
  octomap::OcTreeKey key;
  std::uint32_t count = 0;
  Eigen::Vector3f sum_w = Eigen::Vector3f::Zero();  // sum of point positions [m]
  std::uint32_t rgb_sum[3] = {0, 0, 0};
  std::uint8_t n_labels = 0;
  ClassId ids[kSlots] = {};
  float prob_sum[kSlots] = {};

  Eigen::Vector3f centroid_w() const { return sum_w / float(count); }
  VoxelObservation observation(int k, bool has_color) const;
};

struct VoxelSet {
  std::vector<Voxel> voxels;  // in order of first point: deterministic
  KeyIndexMap index;          // packed key -> position in voxels
  std::size_t points_out_of_bounds = 0;
};

// Groups cloud's points into voxels of `resolution_m` (OctoMap keys, 16-bit, centred at 0).
// Fixed-size chunks of points are voxelized in parallel and merged in chunk order, so the result
// (voxel order and float sums) is the same for any thread count. `chunks` is reusable scratch.
void voxelize(const LabeledCloud& cloud, double resolution_m, VoxelSet& out, std::vector<VoxelSet>& chunks);

}  // namespace s3m::mapping
