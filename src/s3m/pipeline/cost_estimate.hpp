#pragma once
// What one integrated frame will cost the map, estimated from the settings and the camera before
// the first frame, so that settings which would run for hours or exhaust memory are refused up
// front with the keys to change (`cloud.pixel_stride: 1`, `map.resolution_m: 0.005`,
// `cloud.max_depth_m: 100` together ran until killed). Every number is an upper bound for open space; a
// room ends the rays at its walls (measured: 8-12x below the bound, cost_estimate.cpp).
#include <string>

#include "s3m/core/camera.hpp"
#include "s3m/pipeline/pipeline_config.hpp"

namespace s3m::pipeline {

struct CostEstimate {
  double rays = 0;            // back-projected pixels per frame: ceil(W / stride) * ceil(H / stride)
  double ray_length_m = 0;    // free space is cleared up to min(cloud.max_depth_m, map.insert.max_range_m) [m]
  double voxels_per_ray = 0;  // ray_length_m / map.resolution_m (1 without free-space clearing)
  double frustum_voxels = 0;  // voxels in the view pyramid of that depth: R^3 (W/fx) (H/fy) / 3 / res^3
  double voxel_updates = 0;   // min(rays * voxels_per_ray, frustum_voxels): distinct voxels a frame touches
  double map_bytes = 0;       // voxel_updates * kMapBytesPerVoxel: worst-case map growth per frame [bytes]
  double cloud_bytes = 0;     // one kept cloud at most: rays * (12 + 3 + 6 * segmenter.top_k) [bytes]
  double kept_clouds = 0;     // clouds cloud.kept_clouds_budget_mb holds at that size (0 when unlimited)
  double map_extent_m = 0;    // edge of the 16-level octree, 2^16 * resolution; farther points are dropped [m]
};

// Limits on CostEstimate::voxel_updates per integrated frame; how they were chosen: cost_estimate.cpp.
inline constexpr double kWarnVoxelUpdates = 1e7;  // above: a warning line before the first frame
inline constexpr double kMaxVoxelUpdates = 1e8;   // above: refused unless forced (`s3m run --force`)
inline constexpr double kMapBytesPerVoxel = 74;   // SemanticOcTree memory per leaf, inner nodes included

CostEstimate estimate_cost(const PipelineConfig& config, const PinholeCamera& camera);

// Throws s3m::Error naming the keys, the estimate and the limit when voxel_updates > kMaxVoxelUpdates
// and not `force`; logs one warning line when the estimate is large (> kWarnVoxelUpdates, or forced)
// or when the kept-cloud budget holds less than one cloud. Call before the first frame (s3m run,
// s3m_node). force_option: how the user forces, named in the messages (s3m_node: "~force:=true").
void check_cost(const PipelineConfig& config, const PinholeCamera& camera, bool force,
                const std::string& force_option = "--force");

}  // namespace s3m::pipeline
