#pragma once
// Ground-truth semantic voxel map of a scene: every voxel that a visible surface passes through,
// with the class of the surface (majority of surface samples in the voxel). Surfaces outside the
// room (the walls' outer faces) and faces buried inside other primitives are left out.
#include "s3m/io/gt_voxels.hpp"
#include "s3m/sim/scene.hpp"

namespace s3m::sim {

// Voxels sorted by (z, y, x) index, so the output is deterministic. resolution_m > 0.
io::GtVoxelMap voxelize_scene(const Scene& scene, double resolution_m);

}  // namespace s3m::sim
