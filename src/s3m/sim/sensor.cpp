#include "s3m/sim/sensor.hpp"

#include <cmath>

#include "s3m/core/config_table.hpp"
#include "s3m/core/error.hpp"
#include "s3m/core/yaml_util.hpp"

namespace s3m::sim {

void SensorConfig::validate() const {
  camera.validate();
  require(min_depth_m >= 0 && max_depth_m > min_depth_m, "sensor: need 0 <= min_depth_m < max_depth_m");
  require(max_depth_m * camera.depth_factor <= 65535.0,
          "sensor: max_depth_m * depth_factor must fit a 16-bit PNG (<= 65535)");
  require(depth_sigma0_m >= 0 && depth_sigma_k >= 0, "sensor: depth noise parameters must be >= 0");
  require(edge_jump_rel > 0, "sensor: edge_jump_rel must be > 0");
  for (double p : {edge_dropout, dark_dropout, random_dropout})
    require(p >= 0 && p <= 1, "sensor: dropout probabilities must be in [0, 1]");
  require(grazing_cos >= 0 && grazing_cos < 1, "sensor: grazing_cos must be in [0, 1)");
  require(rgb_sigma >= 0 && optics_blur_px >= 0, "sensor: rgb_sigma and optics_blur_px must be >= 0");
  require(motion_blur_samples >= 1 && motion_blur_samples <= 32,
          "sensor: motion_blur_samples must be in 1..32");
  require(exposure_s >= 0, "sensor: exposure_s must be >= 0");
  require(std::abs(depth_time_offset_s) <= 0.5, "sensor: depth_time_offset_s must be within [-0.5, 0.5] s");
  require(time_jitter_s >= 0 && time_jitter_s <= 0.05, "sensor: time_jitter_s must be in [0, 0.05] s");
  require(disparity_step_px >= 0 && disparity_step_px <= 1, "sensor: disparity_step_px must be in [0, 1] px");
  require(disparity_baseline_m > 0 && disparity_baseline_m <= 1,
          "sensor: disparity_baseline_m must be in (0, 1] m");
  require(edge_fattening_px >= 0 && edge_fattening_px <= 10, "sensor: edge_fattening_px must be in 0..10");
  require(std::abs(depth_registration_error_px) <= 20,
          "sensor: depth_registration_error_px must be within [-20, 20] px");
}

void fields(config::FieldVisitor& v, SensorConfig& c) {
  // The camera's intrinsics sit flat in `sensor:`, next to the noise model.
  v("fx", c.camera.fx);
  v("fy", c.camera.fy);
  v("cx", c.camera.cx);
  v("cy", c.camera.cy);
  v("width", c.camera.width);
  v("height", c.camera.height);
  v("depth_factor", c.camera.depth_factor);
  v("min_depth_m", c.min_depth_m);
  v("max_depth_m", c.max_depth_m);
  v("noise", c.noise);
  v("depth_sigma0_m", c.depth_sigma0_m);
  v("depth_sigma_k", c.depth_sigma_k);
  v("edge_jump_rel", c.edge_jump_rel);
  v("edge_dropout", c.edge_dropout);
  v("dark_albedo", c.dark_albedo);
  v("dark_dropout", c.dark_dropout);
  v("grazing_cos", c.grazing_cos);
  v("random_dropout", c.random_dropout);
  v("rgb_sigma", c.rgb_sigma);
  v("optics_blur_px", c.optics_blur_px);
  v("motion_blur_samples", c.motion_blur_samples);
  v("exposure_s", c.exposure_s);
  v("depth_time_offset_s", c.depth_time_offset_s);
  v("time_jitter_s", c.time_jitter_s);
  v("rolling_shutter_s", c.camera.rolling_shutter_s);
  v("disparity_step_px", c.disparity_step_px);
  v("disparity_baseline_m", c.disparity_baseline_m);
  v("edge_fattening_px", c.edge_fattening_px);
  v("depth_registration_error_px", c.depth_registration_error_px);
}

void load_sensor_config(const YAML::Node& n, SensorConfig& c, const std::string& ctx) {
  config::read(n, config::table_of(c), ctx);
}

PinholeCamera sensor_camera(const std::string& name, int width, int height) {
  require(width > 0 && height > 0, "sensor_camera: width and height must be positive");
  PinholeCamera c;
  double f640 = 0;
  if (name == "kinect")
    f640 = 525.0;
  else if (name == "d455")
    f640 = 382.6;  // D455 colour/depth at 640x480: ~87 deg horizontal FOV
  else
    throw Error("unknown sensor camera '" + name + "' (expected kinect or d455)");
  const double s = width / 640.0;
  c.fx = c.fy = f640 * s;
  c.cx = (width - 1) / 2.0;
  c.cy = (height - 1) / 2.0;
  c.width = width;
  c.height = height;
  c.depth_factor = 5000.0;
  return c;
}

std::vector<std::string> sensor_profiles() { return {"ideal", "default", "realistic"}; }

void apply_sensor_profile(const std::string& name, SensorConfig& c) {
  require(name == "ideal" || name == "default" || name == "realistic",
          "unknown sensor profile '" + name + "' (expected ideal, default or realistic)");
  // A profile decides what goes wrong and whether; how noisy (sigmas, dropout rates), the range and
  // the camera stay as configured.
  const SensorConfig off;
  c.noise = name != "ideal";
  c.motion_blur_samples = off.motion_blur_samples;
  c.exposure_s = off.exposure_s;
  c.depth_time_offset_s = off.depth_time_offset_s;
  c.time_jitter_s = off.time_jitter_s;
  c.camera.rolling_shutter_s = off.camera.rolling_shutter_s;
  c.disparity_step_px = off.disparity_step_px;
  c.disparity_baseline_m = off.disparity_baseline_m;
  c.edge_fattening_px = off.edge_fattening_px;
  c.depth_registration_error_px = off.depth_registration_error_px;
  if (name != "realistic") return;
  // Kinect v1: colour and depth are free-running streams (up to a frame apart, typically half of
  // one), the colour sensor's rolling readout takes most of the 33 ms frame, and depth is
  // triangulated over a 7.5 cm baseline by block matching in 1/8 px disparity steps.
  c.depth_time_offset_s = 0.015;
  c.time_jitter_s = 0.002;
  c.camera.rolling_shutter_s = 0.025;
  c.motion_blur_samples = 4;
  c.exposure_s = 0.012;
  c.disparity_step_px = 0.125;
  c.disparity_baseline_m = 0.075;
  c.edge_fattening_px = 1;
  c.depth_registration_error_px = 1.0;
}

}  // namespace s3m::sim
