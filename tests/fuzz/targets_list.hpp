#pragma once
// Per-module registration of fuzz targets (one .cpp per module, compiled only when it is built).
#include <vector>

#include "fuzz/targets.hpp"

namespace s3m::fuzz {
void append_io_targets(std::vector<Target>& out);
void append_features_targets(std::vector<Target>& out);
void append_mapping_targets(std::vector<Target>& out);
void append_semantics_targets(std::vector<Target>& out);
void append_pipeline_targets(std::vector<Target>& out);
void append_rosbag2_targets(std::vector<Target>& out);
}  // namespace s3m::fuzz
