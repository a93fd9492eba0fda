#include "s3m/mapping/insert.hpp"

#include <algorithm>
#include <bit>

#include <tbb/task_arena.h>

#include "s3m/core/config_table.hpp"
#include "s3m/core/error.hpp"
#include "s3m/core/thread_count.hpp"
#include "s3m/core/timing.hpp"
#include "s3m/core/yaml_util.hpp"
#include "s3m/mapping/outliers.hpp"

namespace s3m::mapping {

namespace {
enum VoxelState : std::uint8_t { kOccupied = 0, kFar = 1, kTooClose = 2, kOutlier = 3, kDynamic = 4 };
}

void InsertConfig::validate() const {
  require(min_range_m >= 0.0, "insert.min_range_m must be >= 0");
  require(max_range_m > min_range_m, "insert.max_range_m must be > min_range_m");
  require(radius_min_neighbors >= 0 && radius_min_neighbors <= 26,
          "insert.radius_min_neighbors must be in [0, 26]");
  require(min_points_per_voxel >= 1, "insert.min_points_per_voxel must be >= 1");
  require(sor_neighbors >= 0 && sor_neighbors <= 124, "insert.sor_neighbors must be in [0, 124]");
  require(sor_std_mul > 0.0, "insert.sor_std_mul must be > 0");
  require(thread_count_ok(num_threads), "insert.num_threads = " + std::to_string(num_threads) + " must be " +
                                            thread_count_range("all cores"));
}

void fields(config::FieldVisitor& v, InsertConfig& c) {
  v("min_range_m", c.min_range_m);
  v("max_range_m", c.max_range_m);
  v("clear_beyond_max_range", c.clear_beyond_max_range);
  v("clear_free_space", c.clear_free_space);
  v("radius_min_neighbors", c.radius_min_neighbors);
  v("min_points_per_voxel", c.min_points_per_voxel);
  v("sor_neighbors", c.sor_neighbors);
  v("sor_std_mul", c.sor_std_mul);
  v("num_threads", c.num_threads);
}

InsertConfig insert_config_from_yaml(const YAML::Node& node, const std::string& ctx) {
  InsertConfig c;
  if (node) config::read(node, config::table_of(c), ctx);
  return c;
}

Inserter::Inserter(const InsertConfig& cfg, std::vector<ClassId> dynamic)
    : cfg_(cfg), dynamic_(std::move(dynamic)) {
  cfg_.validate();
}

// The label with the largest summed probability over the voxel's points (the one fusion would rank
// first); ties go to the lower id, as in Voxel::observation.
bool Inserter::is_dynamic(const Voxel& v) const {
  if (dynamic_.empty() || v.n_labels == 0) return false;
  int best = 0;
  for (int i = 1; i < v.n_labels; ++i)
    if (v.prob_sum[i] > v.prob_sum[best] || (v.prob_sum[i] == v.prob_sum[best] && v.ids[i] < v.ids[best]))
      best = i;
  return std::find(dynamic_.begin(), dynamic_.end(), v.ids[best]) != dynamic_.end();
}

InsertStats Inserter::insert(const LabeledCloud& cloud, SemanticOcTree& tree) {
  cloud.validate();
  InsertStats stats;
  stats.points = cloud.size();
  const Stopwatch total;
  const KeyCoder coder(tree.getResolution());
  const octomap::point3d origin(cloud.origin.x(), cloud.origin.y(), cloud.origin.z());
  octomap::OcTreeKey origin_key;
  if (!coder.key_checked(origin, origin_key))
    throw Error("insert: sensor origin is outside the map's key range");
  tbb::task_arena arena(cfg_.num_threads > 0 ? cfg_.num_threads : tbb::task_arena::automatic);
  arena.execute([&] {
    // 1. Voxel down-sampling at map resolution: one merged observation per voxel.
    Stopwatch sw;
    voxelize(cloud, tree.getResolution(), voxels_, voxel_chunks_);
    stats.voxels = voxels_.voxels.size();
    stats.points_out_of_bounds = voxels_.points_out_of_bounds;
    // 2. Range limits (on voxel centres, as OctoMap's discretized mode).
    classify_by_range(coder, origin, stats);
    stats.ms_voxelize = sw.elapsed_ms();
    // 3. The frame's bounding box as a dense brick bitmap; occupied bits; outlier removal.
    sw.reset();
    prepare_rays(coder, origin);
    remove_outliers(stats);
    stats.ms_filter = sw.elapsed_ms();
    // 4. Free space: one ray per distinct end voxel (and truncated rays for far voxels).
    sw.reset();
    ray_ends_.clear();
    for (std::size_t i = 0; i < voxels_.voxels.size(); ++i) {
      if (state_[i] == kOccupied || state_[i] == kDynamic)
        ray_ends_.push_back(coder.center(voxels_.voxels[i].key));
      if (state_[i] == kFar && cfg_.clear_beyond_max_range) {
        const octomap::point3d c = coder.center(voxels_.voxels[i].key);
        ray_ends_.push_back(origin + (c - origin).normalized() * float(cfg_.max_range_m));
      }
    }
    if (cfg_.clear_free_space) grid_.cast_rays(coder, origin, ray_ends_);
    stats.rays = cfg_.clear_free_space ? ray_ends_.size() : 0;
    grid_.build_bricks(update_);
    fill_observations(tree, !cloud.rgb.empty());
    stats.ms_raycast = sw.elapsed_ms();
    // 5. One Morton-ordered pass over the tree (parallel subtrees).
    sw.reset();
    tree.applyFrameUpdate(update_);
    stats.ms_tree = sw.elapsed_ms();
  });
  stats.bricks = update_.bricks.size();
  for (const BrickUpdate& b : update_.bricks)
    for (std::uint64_t w : b.free) stats.voxels_free += std::size_t(std::popcount(w));
  stats.ms_total = total.elapsed_ms();
  return stats;
}

void Inserter::classify_by_range(const KeyCoder& coder, const octomap::point3d& origin, InsertStats& stats) {
  state_.assign(voxels_.voxels.size(), kOccupied);
  for (std::size_t i = 0; i < voxels_.voxels.size(); ++i) {
    const double range = (coder.center(voxels_.voxels[i].key) - origin).norm();
    if (range > cfg_.max_range_m)
      state_[i] = kFar, ++stats.voxels_far;
    else if (range < cfg_.min_range_m)
      state_[i] = kTooClose, ++stats.voxels_too_close;
    else if (is_dynamic(voxels_.voxels[i]))
      state_[i] = kDynamic, ++stats.voxels_dynamic;
  }
}

// Sizes the brick grid to the bounding box of the origin, the occupied voxels and the truncated
// ray ends, and sets the occupied bits.
void Inserter::prepare_rays(const KeyCoder& coder, const octomap::point3d& origin) {
  octomap::OcTreeKey lo, hi;
  coder.key_checked(origin, lo);
  hi = lo;
  auto extend = [&](const octomap::OcTreeKey& k) {
    for (int a = 0; a < 3; ++a) lo[a] = std::min(lo[a], k[a]), hi[a] = std::max(hi[a], k[a]);
  };
  for (std::size_t i = 0; i < voxels_.voxels.size(); ++i) {
    if (state_[i] == kOccupied || state_[i] == kDynamic) extend(voxels_.voxels[i].key);
    if (state_[i] == kFar && cfg_.clear_beyond_max_range) {
      const octomap::point3d c = coder.center(voxels_.voxels[i].key);
      octomap::OcTreeKey k;
      if (coder.key_checked(origin + (c - origin).normalized() * float(cfg_.max_range_m), k)) extend(k);
    }
  }
  grid_.reset(lo, hi);
  for (std::size_t i = 0; i < voxels_.voxels.size(); ++i)
    if (state_[i] == kOccupied) grid_.set_occupied(voxels_.voxels[i].key);
}

void Inserter::remove_outliers(InsertStats& stats) {
  const std::vector<bool> drop = find_outliers(voxels_, state_, grid_, cfg_);
  for (std::size_t i = 0; i < drop.size(); ++i) {
    if (!drop[i]) continue;
    state_[i] = kOutlier;
    grid_.clear_occupied(voxels_.voxels[i].key);
    ++stats.voxels_removed_outliers;
  }
  stats.voxels_occupied = std::size_t(std::count(state_.begin(), state_.end(), std::uint8_t(kOccupied)));
}

// Observations in the tree's depth-first order (brick Morton code, then in-brick bit), and each
// brick's index of its first observation.
void Inserter::fill_observations(const SemanticOcTree& tree, bool has_color) {
  std::vector<std::pair<std::uint64_t, std::uint32_t>> order;
  order.reserve(voxels_.voxels.size());
  for (std::size_t i = 0; i < voxels_.voxels.size(); ++i) {
    if (state_[i] != kOccupied) continue;
    const octomap::OcTreeKey& k = voxels_.voxels[i].key;
    order.emplace_back((brick_morton(k[0] >> 3, k[1] >> 3, k[2] >> 3) << 9) | brick_bit(k), std::uint32_t(i));
  }
  std::sort(order.begin(), order.end());
  const int k = tree.fusionConfig().k;
  update_.observations.resize(order.size());
  for (std::size_t j = 0; j < order.size(); ++j)
    update_.observations[j] = voxels_.voxels[order[j].second].observation(k, has_color);
  std::size_t next = 0;
  for (BrickUpdate& b : update_.bricks) {
    b.first_obs = std::uint32_t(next);
    while (next < order.size() && (order[next].first >> 9) == b.morton) ++next;
  }
}

}  // namespace s3m::mapping
