#include "s3m/io/depth_to_colour.hpp"

#include <algorithm>
#include <cmath>

#include <fmt/format.h>
#include <opencv2/calib3d.hpp>

#include "s3m/core/error.hpp"

namespace s3m::io {
namespace {

// Normalised image coordinates (x/z, y/z) of the depth image's pixel corners (u - 0.5, v - 0.5) for
// u = 0..width, v = 0..height, row by row, the depth camera's distortion undone.
std::vector<cv::Point2d> normalised_corners(const PinholeCamera& cam) {
  std::vector<cv::Point2d> px;
  px.reserve(static_cast<std::size_t>(cam.width + 1) * (cam.height + 1));
  for (int v = 0; v <= cam.height; ++v)
    for (int u = 0; u <= cam.width; ++u) px.emplace_back(u - 0.5, v - 0.5);
  if (!cam.has_distortion()) {
    for (cv::Point2d& p : px) p = {(p.x - cam.cx) / cam.fx, (p.y - cam.cy) / cam.fy};
    return px;
  }
  const cv::Matx33d K(cam.fx, 0, cam.cx, 0, cam.fy, cam.cy, 0, 0, 1);
  std::vector<cv::Point2d> out;
  cv::undistortPoints(px, out, K, std::vector<double>(cam.dist.begin(), cam.dist.end()));
  return out;
}

// floor / ceil to int without a libm call (the x86-64 baseline has no rounding instruction).
int floor_int(double x) {
  const int i = static_cast<int>(x);
  return i - (x < i);
}
int ceil_int(double x) {
  const int i = static_cast<int>(x);
  return i + (x > i);
}

}  // namespace

DepthToColour::DepthToColour(const PinholeCamera& depth, const PinholeCamera& colour, const SE3& T_c_d)
    : depth_(depth), colour_(colour), T_c_d_(T_c_d) {
  depth_.validate();
  colour_.validate();
  distorted_ = colour_.has_distortion();
  if (distorted_) {  // (1.2 x the largest undistorted radius of the image's corners)^2: all the image sees
    const cv::Matx33d K(colour_.fx, 0, colour_.cx, 0, colour_.fy, colour_.cy, 0, 0, 1);
    std::vector<cv::Point2d> px{{-0.5, -0.5}, {colour_.width - 0.5, -0.5}, {-0.5, colour_.height - 0.5},
                                {colour_.width - 0.5, colour_.height - 0.5}}, n;
    cv::undistortPoints(px, n, K, std::vector<double>(colour_.dist.begin(), colour_.dist.end()));
    for (const cv::Point2d& p : n) max_r2_ = std::max(max_r2_, 1.44 * (p.x * p.x + p.y * p.y));
  }
  const Mat3 R = T_c_d_.linear();
  for (const cv::Point2d& p : normalised_corners(depth_)) corner_rays_.push_back(R * Vec3(p.x, p.y, 1.0));
}

bool DepthToColour::to_pixel(const Vec3& p_c, cv::Point2d& px) const {
  const double iz = 1.0 / p_c.z();
  double x = p_c.x() * iz, y = p_c.y() * iz;
  if (distorted_) {  // OpenCV's forward model, as cv::projectPoints
    // Beyond the image's own field of view the polynomial can fold back into the image.
    if (x * x + y * y > max_r2_) return false;
    const auto& d = colour_.dist;  // k1 k2 p1 p2 k3
    const double r2 = x * x + y * y, radial = 1 + r2 * (d[0] + r2 * (d[1] + r2 * d[4]));
    const double xd = x * radial + 2 * d[2] * x * y + d[3] * (r2 + 2 * x * x);
    const double yd = y * radial + d[2] * (r2 + 2 * y * y) + 2 * d[3] * x * y;
    x = xd, y = yd;
  }
  px = {colour_.fx * x + colour_.cx, colour_.fy * y + colour_.cy};
  return true;
}

std::string DepthToColour::describe() const {
  const Vec3 t_cm = T_c_d_.translation() * 100;
  return fmt::format("depth camera {}x{} fx {:.1f} at ({:.2f}, {:.2f}, {:.2f}) cm in the colour camera; its depth is "
                     "drawn into the colour camera's {}x{} pixels",
                     depth_.width, depth_.height, depth_.fx, t_cm.x(), t_cm.y(), t_cm.z(), colour_.width, colour_.height);
}

cv::Mat DepthToColour::operator()(const cv::Mat& depth_m) const {
  require(depth_m.type() == CV_32FC1 && depth_m.cols == depth_.width && depth_m.rows == depth_.height,
          "depth to colour: the depth image is " + std::to_string(depth_m.cols) + "x" + std::to_string(depth_m.rows) +
              " (expected CV_32FC1 " + std::to_string(depth_.width) + "x" + std::to_string(depth_.height) +
              ", the depth camera's size)");
  cv::Mat out(colour_.height, colour_.width, CV_32FC1, cv::Scalar(0.0f));
  const Vec3 t = T_c_d_.translation();
  for (int v = 0; v < depth_m.rows; ++v) {
    const float* row = depth_m.ptr<float>(v);
    for (int u = 0; u < depth_m.cols; ++u) {
      const float z = row[u];
      if (!(z > 0.0f) || !std::isfinite(z)) continue;
      // Pixel (u, v) spans corners (u, v) and (u + 1, v + 1) of the (width + 1)-wide corner grid.
      const std::size_t lo_i = static_cast<std::size_t>(v) * (depth_m.cols + 1) + u, hi_i = lo_i + depth_m.cols + 2;
      const Vec3 lo = z * corner_rays_[lo_i] + t, hi = z * corner_rays_[hi_i] + t;
      if (lo.z() <= 0 || hi.z() <= 0) continue;
      cv::Point2d a, b;
      if (!to_pixel(lo, a) || !to_pixel(hi, b)) continue;
      // Far outside the image: nothing to draw (and no int conversion of a huge coordinate).
      if (std::max(a.x, b.x) < -1 || std::min(a.x, b.x) > colour_.width || std::max(a.y, b.y) < -1 ||
          std::min(a.y, b.y) > colour_.height)
        continue;
      // Colour pixels whose centres lie inside the patch; at least the one nearest its centre.
      // (Pixel centres are at integer coordinates, s3m/core/camera.hpp.)
      a.x = std::clamp(a.x, -2.0, colour_.width + 1.0), b.x = std::clamp(b.x, -2.0, colour_.width + 1.0);
      a.y = std::clamp(a.y, -2.0, colour_.height + 1.0), b.y = std::clamp(b.y, -2.0, colour_.height + 1.0);
      int u0 = ceil_int(std::min(a.x, b.x)), u1 = floor_int(std::max(a.x, b.x));
      int v0 = ceil_int(std::min(a.y, b.y)), v1 = floor_int(std::max(a.y, b.y));
      if (u0 > u1) u0 = u1 = floor_int(0.5 * (a.x + b.x) + 0.5);
      if (v0 > v1) v0 = v1 = floor_int(0.5 * (a.y + b.y) + 0.5);
      u0 = std::max(u0, 0), v0 = std::max(v0, 0);
      u1 = std::min(u1, colour_.width - 1), v1 = std::min(v1, colour_.height - 1);
      const float z_c = static_cast<float>(0.5 * (lo.z() + hi.z()));
      for (int y = v0; y <= v1; ++y) {
        float* o = out.ptr<float>(y);
        for (int x = u0; x <= u1; ++x)
          if (o[x] == 0.0f || z_c < o[x]) o[x] = z_c;
      }
    }
  }
  return out;
}

}  // namespace s3m::io
