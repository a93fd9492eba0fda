#include "s3m/core/camera.hpp"

#include <cmath>

#include "s3m/core/error.hpp"

namespace s3m {

void PinholeCamera::validate() const {
  auto finite_positive = [](double v) { return std::isfinite(v) && v > 0; };
  require(finite_positive(fx) && finite_positive(fy),
          "camera: focal lengths fx, fy must be finite and > 0 (got fx=" + std::to_string(fx) +
              ", fy=" + std::to_string(fy) + ")");
  require(std::isfinite(cx) && std::isfinite(cy), "camera: principal point cx, cy must be finite");
  require(rolling_shutter_s >= 0 && rolling_shutter_s <= 0.1,
          "camera: rolling_shutter_s (first row to last) must be in [0, 0.1] s (got " +
              std::to_string(rolling_shutter_s) + ")");
  require(width > 0 && height > 0 && width <= 16384 && height <= 16384,
          "camera: width and height must be in 1..16384 (got " + std::to_string(width) + "x" +
              std::to_string(height) + ")");
  // Intrinsics in normalised units (fx 0.9, cx 0.5) pass the checks above and then run to nonsense:
  // the field of view must be a camera's (< 170 deg).
  const double fov_deg = 2 * std::atan(width / (2 * fx)) * 180 / M_PI;
  require(fov_deg < 170,
          "camera: fx=" + std::to_string(fx) + " px gives a " + std::to_string(int(fov_deg)) +
              " deg field of view over " + std::to_string(width) +
              " px (expected fx in pixels of this image, e.g. ~525 at 640 px; normalised intrinsics "
              "must be multiplied by the image size)");
  // A principal point far off the image is a unit or crop mistake, not a lens: the image enlarged by
  // half its size on every side still allows off-centre crops.
  require(cx >= -0.5 * width && cx <= 1.5 * width && cy >= -0.5 * height && cy <= 1.5 * height,
          "camera: principal point cx=" + std::to_string(cx) + ", cy=" + std::to_string(cy) +
              " px lies far outside the " + std::to_string(width) + "x" + std::to_string(height) +
              " px image (expected near its centre, cx in " + std::to_string(-0.5 * width) + ".." +
              std::to_string(1.5 * width) + ", cy in " + std::to_string(-0.5 * height) + ".." +
              std::to_string(1.5 * height) + "; in pixels of this image)");
  require(finite_positive(depth_factor),
          "camera: depth_factor must be finite and > 0 (got " + std::to_string(depth_factor) + ")");
  for (double d : dist) require(std::isfinite(d), "camera: distortion coefficients must be finite");
  require(std::isfinite(bf) && bf >= 0, "camera: bf (baseline times fx) must be finite and >= 0");
}

bool PinholeCamera::has_distortion() const {
  for (double d : dist)
    if (d != 0.0) return true;
  return false;
}

PinholeCamera PinholeCamera::scaled(double s) const {
  PinholeCamera c = *this;
  c.fx *= s;
  c.fy *= s;
  // Pixel-centre convention: centre of pixel 0 stays at 0 after scaling about the corner (-0.5, -0.5).
  c.cx = (cx + 0.5) * s - 0.5;
  c.cy = (cy + 0.5) * s - 0.5;
  c.width = static_cast<int>(std::lround(width * s));
  c.height = static_cast<int>(std::lround(height * s));
  c.bf *= s;
  return c;
}

std::optional<PinholeCamera> camera_preset(const std::string& name) {
  // Values from the TUM RGB-D benchmark's "Intrinsic Camera Calibration of the Kinect" page.
  PinholeCamera c;
  c.depth_factor = 5000.0;
  if (name == "tum_fr1") {
    c.fx = 517.3;
    c.fy = 516.5;
    c.cx = 318.6;
    c.cy = 255.3;
    c.dist = {0.2624, -0.9531, -0.0054, 0.0026, 1.1633};
  } else if (name == "tum_fr2") {
    c.fx = 520.9;
    c.fy = 521.0;
    c.cx = 325.1;
    c.cy = 249.7;
    c.dist = {0.2312, -0.7849, -0.0033, -0.0001, 0.9172};
  } else if (name == "tum_fr3") {
    c.fx = 535.4;
    c.fy = 539.2;
    c.cx = 320.1;
    c.cy = 247.6;
    c.dist = {0, 0, 0, 0, 0};
  } else if (name == "7scenes") {
    // Microsoft 7-Scenes' published nominal intrinsics (no per-device calibration, no distortion);
    // depth in millimetres. The raw Kinect depth is not registered to these colour pixels.
    c.fx = c.fy = 585.0;
    c.cx = 320.0;
    c.cy = 240.0;
    c.depth_factor = 1000.0;
  } else if (name == "replica") {
    // Replica as NICE-SLAM renders it (its cam_params.json): 1200x680, depth 6553.5 per metre.
    c.fx = c.fy = 600.0;
    c.cx = 599.5;
    c.cy = 339.5;
    c.width = 1200;
    c.height = 680;
    c.depth_factor = 6553.5;
  } else {
    return std::nullopt;
  }
  return c;
}

}  // namespace s3m
