#include "s3m/pipeline/unregistered_depth.hpp"

#include <algorithm>
#include <vector>

#include <spdlog/spdlog.h>

#include "s3m/core/error.hpp"
#include "s3m/features/depth_registration.hpp"
#include "s3m/pipeline/depth_scale.hpp"

namespace s3m::pipeline {

namespace {

// 0.02 z over 7x7 px instead of 0.05 z over 5x5: depth that is not the colour camera's own is
// least reliable at depth discontinuities (keys at their default only).
void use_strict_keypoint_depth_test(features::FeatureConfig& f) {
  const features::FeatureConfig d;
  if (f.depth_discontinuity_ratio == d.depth_discontinuity_ratio) f.depth_discontinuity_ratio = 0.02;
  if (f.depth_window_px == d.depth_window_px) f.depth_window_px = 3;
}

}  // namespace

void use_unregistered_depth_settings(slam::SlamConfig& slam) {
  const slam::SlamConfig d;
  auto& f = slam.features;
  use_strict_keypoint_depth_test(f);
  if (f.depth_noise.model == d.features.depth_noise.model) f.depth_noise.model = "virtual_right";
  if (slam.mapper.dense_links.enabled == d.mapper.dense_links.enabled)
    slam.mapper.dense_links.enabled = false;
}

bool is_seven_scenes_depth_camera(const PinholeCamera& camera) {
  const PinholeCamera n = *camera_preset("7scenes");
  return camera.fx == n.fx && camera.fy == n.fy && camera.cx == n.cx && camera.cy == n.cy &&
         camera.width == n.width && camera.height == n.height && camera.depth_factor == n.depth_factor &&
         camera.dist == n.dist;
}

void use_nominal_rig_depth_settings(slam::SlamConfig& slam) {
  const slam::SlamConfig d;
  use_strict_keypoint_depth_test(slam.features);
  // Dense links at half resolution: on this depth (Kinect noise, resampled through a nominal rig)
  // they agree with tracking as well as at full resolution for a quarter of the cost (see
  // docs/DECISIONS.md, "7-Scenes rig").
  auto& links = slam.mapper.dense_links;
  if (links.downsample == d.mapper.dense_links.downsample) links.downsample = 2;
}

std::string resolve_depth_registration(PipelineConfig& config, const std::vector<RgbdFrame>& sample,
                                       const PinholeCamera& camera, const std::string& registered_by,
                                       bool may_use_rig) {
  const std::string& mode = config.dataset.depth_registration;
  std::string why = "dataset.depth_registration: " + mode;
  bool registered = mode == "registered";
  if (mode == "auto" && !registered_by.empty()) {
    // The edge check would measure the alignment's own resampling (a nearest-surface splat widens
    // foreground edges by up to a pixel) and could call exactly aligned depth unregistered.
    registered = true;
    why = "aligned to colour by " + registered_by;
  } else if (mode == "auto") {
    const auto check = features::check_depth_registration(sample, camera.cx, camera.cy);
    registered = check.registered;
    why = check.summary;
  }
  if (registered) return "registered (" + why + ")";
  // Read as one 585 px camera, 7-Scenes' depth lands ~8 px and 10 % off its colour pixels; drawn in
  // from its own camera it is the colour pixel's, and the kitchen's trajectory improves (see
  // docs/DECISIONS.md, "7-Scenes rig"). A set "unregistered" keeps one camera.
  if (mode == "auto" && may_use_rig && is_seven_scenes_depth_camera(camera)) {
    config.dataset.camera = "7scenes_kinect_v1";
    use_nominal_rig_depth_settings(config.slam);
    return "not registered (" + why +
           "); 585 px at 640x480 are 7-Scenes' Kinect v1 depth camera: its depth is "
           "drawn into the colour camera by s3m with the camera preset 7scenes_kinect_v1 (colour 529 px, the "
           "depth "
           "camera 2.5 cm beside it), keypoint depth test 0.02 z over 7x7 px where the config leaves it at "
           "its default";
  }
  use_unregistered_depth_settings(config.slam);
  return "not registered (" + why +
         "): keypoint depth test 0.02 z over 7x7 px, virtual-right depth weight, "
         "dense keyframe links off, where the config leaves them at their defaults";
}

std::string resolve_depth_registration(PipelineConfig& config, const FrameSource& source, bool may_use_rig) {
  const bool check = config.dataset.depth_registration == "auto" && source.depth_registered_by().empty();
  const std::vector<RgbdFrame> sample = check ? sample_frames(source) : std::vector<RgbdFrame>{};
  return resolve_depth_registration(config, sample, source.camera(), source.depth_registered_by(),
                                    may_use_rig);
}

}  // namespace s3m::pipeline
