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

}  // namespace s3m::sim
