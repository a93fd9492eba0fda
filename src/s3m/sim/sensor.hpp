#pragma once
// RGB-D sensor model, loosely a RealSense D455 / Kinect v1 in its 640x480 mode:
// - depth is the z coordinate in the camera frame [m], valid in [min_depth_m, max_depth_m];
// - depth noise is Gaussian with sigma(z) = depth_sigma0_m + depth_sigma_k * z^2 (structured-light
//   and stereo sensors both grow roughly with z^2; Nguyen et al. 2012 fit 0.0012 + 0.0019 (z-0.4)^2);
// - depth is missing at depth discontinuities (edge_dropout), on dark surfaces (dark_dropout),
//   at grazing incidence and at random (random_dropout);
// - the colour image is slightly blurred (optics), noisy, and optionally motion-blurred.
// Off by default (so that sequences rendered before them stay byte-identical), the ways real RGB-D
// cameras deceive a SLAM system beyond noise (sensor_effects.hpp, profile "realistic"):
// - timing: depth captured depth_time_offset_s after colour, each stream's instant jittered, the
//   colour rows read out one after another (rolling shutter);
// - structured-light depth: disparity quantised in sub-pixel steps, foreground fattened at edges;
// - registration: depth rendered from a camera turned slightly against the colour camera and
//   stored as if registered to it.
// Time stamps written for each stream are its true capture instants (device clocks, as OpenNI and
// librealsense report them): the colour stamp is the end of row 0's exposure, the depth stamp the
// depth snapshot's instant. Poses in groundtruth.txt are the colour camera's at the colour stamp.
// All random draws are seeded per frame and pixel (see rng.hpp): deterministic and thread-independent.
#include <string>
#include <vector>

#include <yaml-cpp/yaml.h>

#include "s3m/core/camera.hpp"

namespace s3m::config {
class FieldVisitor;
}

namespace s3m::sim {

struct SensorConfig {
  PinholeCamera camera;           // intrinsics and size; depth_factor for the PNGs
  double min_depth_m = 0.3;       // closer surfaces give no depth
  double max_depth_m = 8.0;       // farther surfaces give no depth
  bool noise = true;              // master switch for every random imperfection below
  double depth_sigma0_m = 0.001;  // depth noise at z = 0 [m]
  double depth_sigma_k = 0.0015;  // depth noise growth [1/m]: sigma(z) = sigma0 + k z^2
  double edge_jump_rel = 0.04;    // a neighbour deeper by more than this fraction of z marks an edge
  double edge_dropout = 0.5;      // probability that an edge pixel has no depth
  double dark_albedo = 0.06;      // surfaces darker than this (luminance of albedo) ...
  double dark_dropout = 0.7;      // ... lose depth with this probability
  double grazing_cos = 0.08;      // cos(incidence) below this: no depth
  double random_dropout = 0.002;  // per-pixel probability of a missing depth value
  double rgb_sigma = 2.0;         // colour noise [8-bit levels]
  double optics_blur_px = 0.6;    // Gaussian blur sigma of the lens [px]; 0 = off
  int motion_blur_samples = 1;    // > 1: average this many poses over the exposure
  double exposure_s = 0.012;      // exposure time for motion blur [s]
  // Sensor lies (sensor_effects.hpp); 0 = off. The rolling shutter is the camera's
  // (camera.rolling_shutter_s: it goes into the recording's camera.yaml like the intrinsics).
  double depth_time_offset_s = 0.0;          // depth instant minus colour instant [s]; < 0: depth leads
  double time_jitter_s = 0.0;                // sigma of each stream's capture instant, per frame [s]
  double disparity_step_px = 0.0;            // depth quantised to this disparity step [px] (Kinect v1: 1/8)
  double disparity_baseline_m = 0.075;       // projector-camera baseline of that quantisation [m]
  int edge_fattening_px = 0;                 // foreground depth bleeds this far into the background [px]
  double depth_registration_error_px = 0.0;  // depth image shifted against colour along u [px]

  void validate() const;  // throws s3m::Error naming the bad field
  double depth_sigma_m(double z_m) const { return depth_sigma0_m + depth_sigma_k * z_m * z_m; }
  // True when frames need poses at other instants or a second camera (Renderer::render_timed).
  bool timed() const {
    return depth_time_offset_s != 0 || time_jitter_s > 0 || camera.rolling_shutter_s > 0 ||
           depth_registration_error_px != 0;
  }
};

// Named sensor mixes for `s3m sim --sensor-profile`. Each sets `noise`, the motion blur and every
// lie above; sigmas, dropout rates, range and camera stay as configured. "default": noise on, no
// lies, no motion blur (the built-in SensorConfig); "ideal": the same with noise off; "realistic": a
// Kinect v1 as it behaves: 15 ms colour-depth offset, 2 ms jitter, 25 ms rolling shutter, motion
// blur over 12 ms (4 samples), 1/8 px disparity steps, 1 px fattening, 1 px misregistration.
// Throws s3m::Error for an unknown name.
void apply_sensor_profile(const std::string& name, SensorConfig& cfg);
std::vector<std::string> sensor_profiles();

// Reads the keys of SensorConfig (plus fx, fy, cx, cy, width, height) from a YAML map.
void load_sensor_config(const YAML::Node& node, SensorConfig& cfg, const std::string& ctx);
// Its YAML keys with the members they fill (core/config_table.hpp).
void fields(config::FieldVisitor& v, SensorConfig& c);

// Named intrinsics: "kinect" (fx = fy = 525, TUM-like), "d455" (fx = fy = 382.6 at 640x480).
// Scaled to width x height (keeping the field of view). Throws s3m::Error for an unknown name.
PinholeCamera sensor_camera(const std::string& name, int width, int height);

}  // namespace s3m::sim
