#pragma once
// Insertion of one labelled point cloud into a SemanticOcTree: the map stage's process().
#include <string>

#include <yaml-cpp/yaml.h>

#include "s3m/mapping/brick_grid.hpp"
#include "s3m/mapping/frame_update.hpp"
#include "s3m/mapping/labeled_cloud.hpp"
#include "s3m/mapping/semantic_octree.hpp"
#include "s3m/mapping/voxelize.hpp"

namespace s3m::config {
class FieldVisitor;
}

namespace s3m::mapping {

struct InsertConfig {
  // Ranges are measured from the sensor origin to the centre of a point's voxel, as OctoMap's
  // discretized insertion does.
  double min_range_m = 0.0;            // closer voxels are ignored (robot body, sensor noise)
  double max_range_m = 4.0;            // farther voxels are not marked occupied ...
  bool clear_beyond_max_range = true;  // ... but clear free space up to max_range_m
  bool clear_free_space = true;        // false: only occupied updates (no ray casting)
  // Radius outlier removal (voxel level): keep a voxel only if at least this many of its 26
  // neighbours are occupied in the same frame. 0 disables it.
  int radius_min_neighbors = 1;
  int min_points_per_voxel = 1;  // drop voxels supported by fewer points (flying pixels)
  // Statistical outlier removal on voxel centroids (PCL-style): mean distance to the nearest
  // sor_neighbors occupied voxels within 2 voxels; drop voxels above mean + sor_std_mul * std.
  int sor_neighbors = 0;  // 0 disables it
  double sor_std_mul = 2.0;
  int num_threads =
      0;  // 0 = all cores (TBB default), else 1..max_thread_count(); results are identical for any value

  void validate() const;  // throws s3m::Error naming the field
};

// Not validated here: load_mapping_config() validates the whole map section and names the file.
InsertConfig insert_config_from_yaml(const YAML::Node& node, const std::string& ctx);
// Its YAML keys with the members they fill (core/config_table.hpp).
void fields(config::FieldVisitor& v, InsertConfig& c);

struct InsertStats {
  std::size_t points = 0, voxels = 0, voxels_occupied = 0, voxels_removed_outliers = 0, voxels_far = 0;
  std::size_t voxels_too_close = 0, points_out_of_bounds = 0, bricks = 0, rays = 0;
  std::size_t voxels_free = 0;     // distinct free voxels updated (after removing occupied ones)
  std::size_t voxels_dynamic = 0;  // voxels whose top class moves: rays clear up to them, no hit
  double ms_voxelize = 0, ms_filter = 0, ms_raycast = 0, ms_tree = 0, ms_total = 0;
};

class Inserter {
 public:
  // dynamic: classes that move (people). A voxel whose strongest label in the frame is one of them
  // is not made occupied; its ray still clears the free space in front of it, so space a person
  // walked through is cleared again by later views of what stood behind.
  explicit Inserter(const InsertConfig& cfg = {}, std::vector<ClassId> dynamic = {});
  const InsertConfig& config() const { return cfg_; }

  // Integrates cloud (world frame) into tree. Thread-safe only for distinct Inserters/trees.
  InsertStats insert(const LabeledCloud& cloud, SemanticOcTree& tree);

 private:
  void classify_by_range(const KeyCoder& coder, const octomap::point3d& origin, InsertStats& stats);
  void remove_outliers(InsertStats& stats);
  void prepare_rays(const KeyCoder& coder, const octomap::point3d& origin);
  void fill_observations(const SemanticOcTree& tree, bool has_color);

  bool is_dynamic(const Voxel& v) const;

  InsertConfig cfg_;
  std::vector<ClassId> dynamic_;
  // Scratch reused across frames (no steady-state allocation).
  VoxelSet voxels_;
  std::vector<VoxelSet> voxel_chunks_;
  std::vector<std::uint8_t> state_;  // per voxel: 0 occupied, 1 far, 2 too close, 3 outlier, 4 dynamic
  std::vector<octomap::point3d> ray_ends_;
  BrickGrid grid_;
  FrameUpdate update_;
};

}  // namespace s3m::mapping
