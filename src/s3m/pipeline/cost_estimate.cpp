#include "s3m/pipeline/cost_estimate.hpp"

#include <algorithm>
#include <cmath>

#include <fmt/format.h>
#include <spdlog/spdlog.h>

#include "s3m/core/classes.hpp"
#include "s3m/core/error.hpp"

namespace s3m::pipeline {

// How the limits were chosen (the measurements on the simulator office: docs/DECISIONS.md, "Map
// cost limits"): a room costs ~3-12 ns and up to ~20 B of RSS per estimated update, and in open space every
// update can be a new leaf of kMapBytesPerVoxel (74 B: the map's memory_bytes / leaf_nodes at 5 mm).
// kMaxVoxelUpdates = 1e8 caps one frame at ~1 s and ~2 GB in a room (7.4 GB in open space, a third
// of this 23 GB machine) and is ~140x above every shipped preset (<= 7.0e5, realsense_d455); kWarnVoxelUpdates =
// 1e7 flags the 1 cm / 5 mm maps that work but grow by hundreds of MB per few frames.
CostEstimate estimate_cost(const PipelineConfig& config, const PinholeCamera& camera) {
  const CloudConfig& cloud = config.cloud;
  const mapping::InsertConfig& insert = config.map.insert;
  const double res = config.map.resolution_m;
  const double stride = cloud.pixel_stride;
  CostEstimate e;
  // backproject() visits u = 0, s, 2s, ... < W: ceil(W / s) columns.
  e.rays = std::ceil(camera.width / stride) * std::ceil(camera.height / stride);
  // Voxels beyond max_range_m get a ray truncated there, or none (clear_beyond_max_range: false).
  e.ray_length_m = std::min(cloud.max_depth_m, insert.max_range_m);
  e.voxels_per_ray = insert.clear_free_space ? e.ray_length_m / res : 1.0;
  const double R = e.ray_length_m / res;
  e.frustum_voxels = R * R * R * (camera.width / camera.fx) * (camera.height / camera.fy) / 3.0;
  e.voxel_updates = std::min(e.rays * e.voxels_per_ray, e.frustum_voxels);
  e.map_bytes = e.voxel_updates * kMapBytesPerVoxel;
  const double point_bytes = 3 * sizeof(float) + 3 + config.segmenter.top_k * (sizeof(ClassId) + sizeof(float));
  e.cloud_bytes = e.rays * point_bytes;
  e.kept_clouds = cloud.kept_clouds_budget_mb * 1e6 / e.cloud_bytes;
  e.map_extent_m = 65536.0 * res;
  return e;
}

namespace {

// "cloud.pixel_stride 1 x 640x480 px with map.resolution_m 0.005 and cloud.max_depth_m 100 (rays
// end at map.insert.max_range_m 5): about 3.1e+08 voxel updates per integrated frame"
std::string describe(const PipelineConfig& config, const PinholeCamera& camera, const CostEstimate& e) {
  const auto& insert = config.map.insert;
  std::string s = fmt::format("cloud.pixel_stride {} x {}x{} px with map.resolution_m {:g} and cloud.max_depth_m {:g}",
                              config.cloud.pixel_stride, camera.width, camera.height, config.map.resolution_m,
                              config.cloud.max_depth_m);
  if (!insert.clear_free_space) s += " (map.insert.clear_free_space off: no rays)";
  else if (insert.max_range_m < config.cloud.max_depth_m) s += fmt::format(" (rays end at map.insert.max_range_m {:g})", insert.max_range_m);
  return s + fmt::format(": about {:.2g} voxel updates per integrated frame ({:.0f} rays x {:.0f} voxels, at most the {:.2g} "
                         "voxels of the view; up to {:.1f} GB of map per frame in open space)",
                         e.voxel_updates, e.rays, e.voxels_per_ray, e.frustum_voxels, e.map_bytes / 1e9);
}

}  // namespace

void check_cost(const PipelineConfig& config, const PinholeCamera& camera, bool force,
                const std::string& force_option) {
  const CostEstimate e = estimate_cost(config, camera);
  const std::string what = describe(config, camera, e);
  if (e.voxel_updates > kMaxVoxelUpdates && !force)
    throw Error(fmt::format("run: {} exceeds the limit of {:.0e} (a frame would take seconds and the map could "
                            "outgrow the memory). Raise cloud.pixel_stride or map.resolution_m, lower "
                            "cloud.max_depth_m or map.insert.max_range_m, or pass {} to run anyway",
                            what, kMaxVoxelUpdates, force_option));
  if (e.voxel_updates > kWarnVoxelUpdates)
    spdlog::warn("run: {}{}: expect slow frames and a large map", what,
                 e.voxel_updates > kMaxVoxelUpdates
                     ? fmt::format(", above the limit of {:.0e} ({})", kMaxVoxelUpdates, force_option)
                     : fmt::format(", allowed up to {:.0e}", kMaxVoxelUpdates));
  if (config.cloud.kept_clouds_budget_mb > 0 && e.kept_clouds < 1)
    spdlog::warn("run: cloud.kept_clouds_budget_mb {:g} holds no cloud of up to {:.1f} MB: loop corrections will "
                 "re-integrate few or no clouds (raise the budget or cloud.keyframe_voxel_m)",
                 config.cloud.kept_clouds_budget_mb, e.cloud_bytes / 1e6);
}

}  // namespace s3m::pipeline
