#pragma once
// Noise removal on the voxelized frame (the paper's "noise removal" before insertion). Working on
// voxels rather than raw points keeps it linear in the voxel count and cheap at 2 cm.
#include <cstdint>
#include <vector>

#include "s3m/mapping/brick_grid.hpp"
#include "s3m/mapping/voxelize.hpp"

namespace s3m::mapping {

struct InsertConfig;

// drop[i] for voxels that fail the point-count, radius or statistical test. Only voxels with
// state[i] == 0 (occupied candidates, as set in grid) are tested; decisions use the unfiltered
// frame, so they do not depend on evaluation order or thread count.
std::vector<bool> find_outliers(const VoxelSet& voxels, const std::vector<std::uint8_t>& state,
                                const BrickGrid& grid, const InsertConfig& cfg);

}  // namespace s3m::mapping
