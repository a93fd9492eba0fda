#include "s3m/mapping/voxelize.hpp"

#include <bit>
#include <cmath>

#include <tbb/parallel_for.h>

namespace s3m::mapping {

void KeyIndexMap::clear(std::size_t expected) {
  std::size_t cap = std::max<std::size_t>(1024, std::bit_ceil(expected * 2));
  if (keys_.size() < cap) {
    keys_.assign(cap, kEmpty);
    vals_.resize(cap);
  } else {
    std::fill(keys_.begin(), keys_.end(), kEmpty);
  }
  shift_ = 64 - std::countr_zero(keys_.size());
  size_ = 0;
}

std::uint32_t KeyIndexMap::find_or_insert(std::uint64_t key, std::uint32_t next, bool& inserted) {
  if (2 * (size_ + 1) > keys_.size()) grow();
  const std::size_t mask = keys_.size() - 1;
  for (std::size_t i = (key * 0x9E3779B97F4A7C15ull) >> shift_;; i = (i + 1) & mask) {
    if (keys_[i] == key) {
      inserted = false;
      return vals_[i];
    }
    if (keys_[i] == kEmpty) {
      keys_[i] = key;
      vals_[i] = next;
      ++size_;
      inserted = true;
      return next;
    }
  }
}

long KeyIndexMap::find(std::uint64_t key) const {
  if (keys_.empty()) return -1;
  const std::size_t mask = keys_.size() - 1;
  for (std::size_t i = (key * 0x9E3779B97F4A7C15ull) >> shift_;; i = (i + 1) & mask) {
    if (keys_[i] == key) return long(vals_[i]);
    if (keys_[i] == kEmpty) return -1;
  }
}

void KeyIndexMap::grow() {
  std::vector<std::uint64_t> old_keys(std::max<std::size_t>(2048, keys_.size() * 2), kEmpty);
  std::vector<std::uint32_t> old_vals(old_keys.size());
  old_keys.swap(keys_);
  old_vals.swap(vals_);
  shift_ = 64 - std::countr_zero(keys_.size());
  size_ = 0;
  bool inserted = false;
  for (std::size_t i = 0; i < old_keys.size(); ++i)
    if (old_keys[i] != kEmpty) find_or_insert(old_keys[i], old_vals[i], inserted);
}

VoxelObservation Voxel::observation(int k, bool has_color) const {
  VoxelObservation o;
  LabelSet all;
  // Mean probability over the voxel's points; slots are in first-seen order, normalise() sorts.
  std::array<int, kSlots> order{};
  for (int i = 0; i < n_labels; ++i) order[i] = i;
  std::partial_sort(order.begin(), order.begin() + std::min<int>(n_labels, kMaxLabels), order.begin() + n_labels,
                    [&](int a, int b) { return prob_sum[a] != prob_sum[b] ? prob_sum[a] > prob_sum[b] : ids[a] < ids[b]; });
  for (int i = 0; i < std::min<int>(n_labels, kMaxLabels); ++i)
    all.push(ids[order[i]], prob_sum[order[i]] / float(count));
  all.normalise(k);
  o.labels = all;
  if (has_color && count > 0) {
    o.has_color = true;
    o.color = {std::uint8_t((rgb_sum[0] + count / 2) / count), std::uint8_t((rgb_sum[1] + count / 2) / count),
               std::uint8_t((rgb_sum[2] + count / 2) / count)};
  }
  return o;
}

namespace {
// slot_cache[j]: the voxel slot label j of the previous point went to; neighbouring points
// usually carry the same label list, so this skips the linear search.
void accumulate(Voxel& v, const LabeledCloud& cloud, std::size_t i, int* slot_cache) {
  ++v.count;
  v.sum_w += cloud.points[i];
  if (!cloud.rgb.empty()) {
    v.rgb_sum[0] += cloud.rgb[3 * i], v.rgb_sum[1] += cloud.rgb[3 * i + 1], v.rgb_sum[2] += cloud.rgb[3 * i + 2];
  }
  for (int j = 0; j < cloud.k; ++j) {
    const ClassId id = cloud.labels[i * cloud.k + j];
    const float p = cloud.probs[i * cloud.k + j];
    int s = slot_cache[j];
    if (s >= v.n_labels || v.ids[s] != id) {
      s = 0;
      while (s < v.n_labels && v.ids[s] != id) ++s;
      slot_cache[j] = s < Voxel::kSlots ? s : 0;
    }
    if (s == v.n_labels) {
      if (s == Voxel::kSlots) continue;  // an 11th distinct label in one voxel: negligible mass
      v.ids[s] = id, v.prob_sum[s] = 0.0f, ++v.n_labels;
    }
    v.prob_sum[s] += p;
  }
}
}  // namespace

namespace {
constexpr std::size_t kChunkPoints = 16384;  // fixed: the merge order must not depend on threads

// floor() without a libm call (the baseline x86-64 target has no SSE4.1 roundsd).
inline int fast_floor(double x) {
  const int i = int(x);
  return i - (x < double(i));
}

void voxelize_range(const LabeledCloud& cloud, std::size_t begin, std::size_t end, double inv_res, VoxelSet& out) {
  out.voxels.clear();
  out.index.clear(out.voxels.capacity());
  out.points_out_of_bounds = 0;
  constexpr int kMaxVal = 32768;  // OctoMap's tree_max_val for 16-level trees
  std::uint64_t last_key = ~0ull;
  std::uint32_t last_idx = 0;
  int slot_cache[kMaxLabels] = {};
  for (std::size_t i = begin; i < end; ++i) {
    const Eigen::Vector3f& p = cloud.points[i];
    // Same value as OcTreeBaseImpl::coordToKeyChecked (float coordinate promoted to double).
    const double sx = inv_res * double(p.x()), sy = inv_res * double(p.y()), sz = inv_res * double(p.z());
    if (!(std::fabs(sx) < kMaxVal - 1 && std::fabs(sy) < kMaxVal - 1 && std::fabs(sz) < kMaxVal - 1)) {
      ++out.points_out_of_bounds;  // also catches NaN
      continue;
    }
    const octomap::OcTreeKey key(std::uint16_t(fast_floor(sx) + kMaxVal), std::uint16_t(fast_floor(sy) + kMaxVal),
                                 std::uint16_t(fast_floor(sz) + kMaxVal));
    const std::uint64_t packed = pack_key(key);
    if (packed != last_key) {  // neighbouring pixels usually share a voxel: skip the hash lookup
      bool inserted = false;
      last_idx = out.index.find_or_insert(packed, std::uint32_t(out.voxels.size()), inserted);
      if (inserted) out.voxels.emplace_back().key = key;
      last_key = packed;
    }
    accumulate(out.voxels[last_idx], cloud, i, slot_cache);
  }
}

void merge_into(Voxel& v, const Voxel& o) {
  v.count += o.count;
  v.sum_w += o.sum_w;
  for (int c = 0; c < 3; ++c) v.rgb_sum[c] += o.rgb_sum[c];
  for (int j = 0; j < o.n_labels; ++j) {
    int s = 0;
    while (s < v.n_labels && v.ids[s] != o.ids[j]) ++s;
    if (s == v.n_labels) {
      if (s == Voxel::kSlots) continue;
      v.ids[s] = o.ids[j], v.prob_sum[s] = 0.0f, ++v.n_labels;
    }
    v.prob_sum[s] += o.prob_sum[j];
  }
}
}  // namespace

void voxelize(const LabeledCloud& cloud, double resolution_m, VoxelSet& out, std::vector<VoxelSet>& chunks) {
  const double inv_res = 1.0 / resolution_m;
  const std::size_t n_chunks = (cloud.size() + kChunkPoints - 1) / kChunkPoints;
  if (n_chunks <= 1) {
    voxelize_range(cloud, 0, cloud.size(), inv_res, out);
    return;
  }
  if (chunks.size() < n_chunks) chunks.resize(n_chunks);
  tbb::parallel_for(std::size_t(0), n_chunks, [&](std::size_t c) {
    voxelize_range(cloud, c * kChunkPoints, std::min(cloud.size(), (c + 1) * kChunkPoints), inv_res, chunks[c]);
  });
  out.voxels.clear();
  out.index.clear(out.voxels.capacity());
  out.points_out_of_bounds = 0;
  for (std::size_t c = 0; c < n_chunks; ++c) {
    out.points_out_of_bounds += chunks[c].points_out_of_bounds;
    for (const Voxel& v : chunks[c].voxels) {
      bool inserted = false;
      const std::uint32_t idx = out.index.find_or_insert(pack_key(v.key), std::uint32_t(out.voxels.size()), inserted);
      if (inserted) out.voxels.push_back(v);
      else merge_into(out.voxels[idx], v);
    }
  }
}

}  // namespace s3m::mapping
