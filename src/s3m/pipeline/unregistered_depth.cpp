#include "s3m/pipeline/unregistered_depth.hpp"

#include <algorithm>
#include <vector>

#include <spdlog/spdlog.h>

#include "s3m/core/error.hpp"
#include "s3m/features/depth_registration.hpp"
#include "s3m/pipeline/depth_scale.hpp"

namespace s3m::pipeline {

void use_unregistered_depth_settings(slam::SlamConfig& slam) {
  const slam::SlamConfig d;
  auto& f = slam.features;
  if (f.depth_discontinuity_ratio == d.features.depth_discontinuity_ratio) f.depth_discontinuity_ratio = 0.02;
  if (f.depth_window_px == d.features.depth_window_px) f.depth_window_px = 3;
  if (f.depth_noise.model == d.features.depth_noise.model) f.depth_noise.model = "virtual_right";
  if (slam.mapper.dense_links.enabled == d.mapper.dense_links.enabled) slam.mapper.dense_links.enabled = false;
}

std::string resolve_depth_registration(PipelineConfig& config, const std::vector<RgbdFrame>& sample,
                                       const PinholeCamera& camera, const std::string& registered_by) {
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
  use_unregistered_depth_settings(config.slam);
  return "not registered (" + why + "): keypoint depth test 0.02 z over 7x7 px, virtual-right depth weight, "
         "dense keyframe links off, where the config leaves them at their defaults";
}

std::string resolve_depth_registration(PipelineConfig& config, const FrameSource& source) {
  const bool check = config.dataset.depth_registration == "auto" && source.depth_registered_by().empty();
  const std::vector<RgbdFrame> sample = check ? sample_frames(source) : std::vector<RgbdFrame>{};
  return resolve_depth_registration(config, sample, source.camera(), source.depth_registered_by());
}

}  // namespace s3m::pipeline
