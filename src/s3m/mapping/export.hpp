#pragma once
// Exports of a SemanticOcTree for other tools. All writes are atomic.
#include <string>

#include "s3m/mapping/semantic_octree.hpp"

namespace s3m::mapping {

// octomap::ColorOcTree .ot with the same tree shape and occupancy; each node coloured by the
// palette colour of its top label (unlabelled nodes: their observed RGB). Opens in octovis.
void export_color_octree(const SemanticOcTree& tree, const std::string& path);

// Plain occupancy .bt (octomap::OcTree binary, maximum-likelihood occupancy, as octomap_server).
void export_binary_octree(const SemanticOcTree& tree, const std::string& path);

enum class PlyColor { kObserved, kClass };

// One PLY vertex per occupied finest voxel (centre, world frame [m]) with colour, `label`
// (class id) and `confidence` (its probability). Returns the number of points written.
std::size_t export_ply(const SemanticOcTree& tree, const std::string& path, PlyColor color = PlyColor::kObserved);

}  // namespace s3m::mapping
