#pragma once
// Saving and loading a SemanticOcTree as an OctoMap .ot file with everything (occupancy, colour,
// labels, probabilities, class list, resolution, fusion and occupancy parameters).
// Writes are atomic (io::write_file_atomic: temp file next to the target, fsync, rename).
#include <memory>
#include <string>

#include "s3m/mapping/semantic_octree.hpp"

namespace s3m::mapping {

// Throws s3m::Error (naming the file) when the file cannot be written.
void save_semantic_map(const SemanticOcTree& tree, const std::string& path);

// Throws s3m::Error naming the file and the problem for a missing, truncated, corrupt or
// foreign (e.g. a plain OcTree .ot) file. Never returns a partially read map.
std::unique_ptr<SemanticOcTree> load_semantic_map(const std::string& path);

}  // namespace s3m::mapping
