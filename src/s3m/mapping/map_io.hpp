#pragma once
// Saving and loading a SemanticOcTree as an OctoMap .ot file with everything (occupancy, colour,
// labels, probabilities, class list, resolution, fusion and occupancy parameters).
// Writes are atomic: a temp file next to the target is renamed over it only when complete.
#include <memory>
#include <string>

#include "s3m/mapping/semantic_octree.hpp"

namespace s3m::mapping {

// Throws s3m::Error (naming the file) when the file cannot be written.
void save_semantic_map(const SemanticOcTree& tree, const std::string& path);

// Throws s3m::Error naming the file and the problem for a missing, truncated, corrupt or
// foreign (e.g. a plain OcTree .ot) file. Never returns a partially read map.
std::unique_ptr<SemanticOcTree> load_semantic_map(const std::string& path);

// Writes bytes to path atomically (temp file in the same directory + rename).
void write_atomically(const std::string& path, const std::string& bytes);

}  // namespace s3m::mapping
