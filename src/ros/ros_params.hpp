#pragma once
// The node's parameters mirror the YAML presets: `~config` names a preset (config/*.yaml, "" = the
// built-in defaults) and any preset section given as a private parameter (`~slam`, `~cloud`, `~map`,
// `~segmenter`, `~flow`, `~threads`, `~dataset`, `~eval`, e.g. from <rosparam> in a launch file)
// overrides the preset key by key. The merged document goes through the same parser as `s3m run
// --config`, so unknown keys and bad values are refused with the same messages. `~map` given as a
// string is not the section but the saved run to continue in (NodeParams::map).
#include <string>

#include <ros/node_handle.h>
#include <yaml-cpp/yaml.h>

#include "s3m/pipeline/pipeline_config.hpp"

namespace s3m::ros1 {

// Recursively merges `overrides` into `base` (maps key by key; anything else replaces).
YAML::Node merge_yaml(YAML::Node base, const YAML::Node& overrides);

// Reads ~config and the section overrides from the private node handle.
pipeline::PipelineConfig config_from_params(const ros::NodeHandle& pnh);

}  // namespace s3m::ros1
