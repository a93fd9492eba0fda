#pragma once
// A run adapts to depth that is not registered to colour (dataset.depth_registration): decided
// before the first frame from a few frames' edges (features::check_depth_registration), or set.
#include <string>
#include <vector>

#include "s3m/pipeline/frame_source.hpp"
#include "s3m/pipeline/pipeline_config.hpp"

namespace s3m::pipeline {

// The overlays (config_overlays.hpp) of the two decisions below: SLAM settings for depth that is
// not the colour camera's, read as one camera (a stricter keypoint depth test, ORB-SLAM's
// virtual-right depth weight, dense keyframe links off), and for 7-Scenes depth drawn into the
// colour camera through a nominal rig (the stricter depth test, dense links at half resolution).
inline constexpr const char* kUnregisteredDepthOverlay = "unregistered_depth";
inline constexpr const char* kSevenScenesRigOverlay = "7scenes_rig";

// Microsoft 7-Scenes' published intrinsics (fx = fy = 585 px, principal point (320, 240), 640x480,
// depth in millimetres, no distortion): its Kinect v1's depth camera, not its colour camera.
bool is_seven_scenes_depth_camera(const PinholeCamera& camera);

// Resolves config.dataset.depth_registration: "auto" takes `registered_by` (FrameSource::
// depth_registered_by()) when the source knows, else checks the frames of `sample` (their colour
// and depth edges); when the depth is not registered (checked or set) the overlay
// unregistered_depth is applied to the keys config.written does not hold. Depth found unregistered
// beside 7-Scenes' intrinsics is that dataset's Kinect v1: when the caller can open the frames
// again (`may_use_rig`) and config.written has no dataset.camera, the overlay 7scenes_rig is
// applied instead, which sets dataset.camera to "7scenes_kinect_v1" (the two cameras; the caller
// reopens the frames with it). Returns what was decided and why, with what the overlay set and
// left, for the log and metrics.json.
std::string resolve_depth_registration(PipelineConfig& config, const std::vector<RgbdFrame>& sample,
                                       const PinholeCamera& camera, const std::string& registered_by = "",
                                       bool may_use_rig = false);

// The same with frames 0, 20, 40, ... (at most 6, within the first 120) of `source`; reads no
// frame unless the mode is "auto".
std::string resolve_depth_registration(PipelineConfig& config, const FrameSource& source,
                                       bool may_use_rig = false);

}  // namespace s3m::pipeline
