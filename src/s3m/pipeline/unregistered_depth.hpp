#pragma once
// A run adapts to depth that is not registered to colour (dataset.depth_registration): decided
// before the first frame from a few frames' edges (features::check_depth_registration), or set.
#include <string>
#include <vector>

#include "s3m/pipeline/frame_source.hpp"
#include "s3m/pipeline/pipeline_config.hpp"

namespace s3m::pipeline {

// The SLAM settings for depth that is not the colour camera's (config/slam_7scenes.yaml; reasons
// there and in docs/RESULTS.md): a stricter keypoint depth test (0.02 z over 7x7 px), ORB-SLAM's
// virtual-right depth weight instead of the sensor model, dense keyframe links off. Only keys
// still at their built-in default change, so a preset's own values stay.
void use_unregistered_depth_settings(slam::SlamConfig& slam);

// Resolves config.dataset.depth_registration: "auto" takes `registered_by` (FrameSource::
// depth_registered_by()) when the source knows, else checks the frames of `sample` (their colour
// and depth edges); when the depth is not registered (checked or set) the settings above are
// applied. Returns what was decided and why, for the log and metrics.json.
std::string resolve_depth_registration(PipelineConfig& config, const std::vector<RgbdFrame>& sample,
                                       const PinholeCamera& camera, const std::string& registered_by = "");

// The same with frames 0, 20, 40, ... (at most 6, within the first 120) of `source`; reads no
// frame unless the mode is "auto".
std::string resolve_depth_registration(PipelineConfig& config, const FrameSource& source);

}  // namespace s3m::pipeline
