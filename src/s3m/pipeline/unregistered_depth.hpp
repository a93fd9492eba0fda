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

// Microsoft 7-Scenes' published intrinsics (fx = fy = 585 px, principal point (320, 240), 640x480,
// depth in millimetres, no distortion): its Kinect v1's depth camera, not its colour camera.
bool is_seven_scenes_depth_camera(const PinholeCamera& camera);

// For depth that s3m draws into the colour camera from a nominal rather than calibrated rig
// (io::camera_file_preset("7scenes_kinect_v1")): the stricter keypoint depth test of the settings
// above, dense keyframe links at half resolution; the depth weight and the links themselves stay
// those of registered depth. Keys at their default only.
void use_nominal_rig_depth_settings(slam::SlamConfig& slam);

// Resolves config.dataset.depth_registration: "auto" takes `registered_by` (FrameSource::
// depth_registered_by()) when the source knows, else checks the frames of `sample` (their colour
// and depth edges); when the depth is not registered (checked or set) the settings above are
// applied. Depth found unregistered beside 7-Scenes' intrinsics is that dataset's Kinect v1: when
// the caller can open the frames again (`may_use_rig`), config.dataset.camera becomes
// "7scenes_kinect_v1" (the two cameras; the caller reopens the frames with it) and the rig's
// settings are applied instead. Returns what was decided and why, for the log and metrics.json.
std::string resolve_depth_registration(PipelineConfig& config, const std::vector<RgbdFrame>& sample,
                                       const PinholeCamera& camera, const std::string& registered_by = "",
                                       bool may_use_rig = false);

// The same with frames 0, 20, 40, ... (at most 6, within the first 120) of `source`; reads no
// frame unless the mode is "auto".
std::string resolve_depth_registration(PipelineConfig& config, const FrameSource& source,
                                       bool may_use_rig = false);

}  // namespace s3m::pipeline
