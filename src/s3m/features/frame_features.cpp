#include "s3m/features/frame_features.hpp"

#include <algorithm>
#include <cmath>

#include <opencv2/calib3d.hpp>
#include <opencv2/imgproc.hpp>

#include "s3m/core/error.hpp"

namespace s3m::features {
namespace {

// Depth [m] at pixel (u, v), or 0 when missing, out of range, or on a depth discontinuity.
float keypoint_depth(const cv::Mat& depth, float u, float v, const FeatureConfig& c) {
  const int x = cvRound(u), y = cvRound(v);
  if (x < 0 || y < 0 || x >= depth.cols || y >= depth.rows) return 0.0f;
  const float z = depth.at<float>(y, x);
  if (!(z >= c.min_depth_m && z <= c.max_depth_m)) return 0.0f;
  float lo = z, hi = z;
  const int w = c.depth_window_px;
  for (int yy = std::max(0, y - w); yy <= std::min(depth.rows - 1, y + w); ++yy) {
    const float* row = depth.ptr<float>(yy);
    for (int xx = std::max(0, x - w); xx <= std::min(depth.cols - 1, x + w); ++xx) {
      const float d = row[xx];
      if (!(d > 0.0f)) continue;  // holes are not edges; NaN fails the test too
      lo = std::min(lo, d);
      hi = std::max(hi, d);
    }
  }
  if ((hi - lo) > c.depth_discontinuity_ratio * z) return 0.0f;
  // The keypoint is sub-pixel and its map point is back-projected from there: on a slanted surface
  // the nearest pixel's depth is off by up to half a pixel's depth step (3 mm on a floor 2 m away),
  // as much as the keypoint's own position error. Without an edge nearby, interpolate.
  const int x0 = int(std::floor(u)), y0 = int(std::floor(v));
  if (x0 < 0 || y0 < 0 || x0 + 1 >= depth.cols || y0 + 1 >= depth.rows) return z;
  const float d00 = depth.at<float>(y0, x0), d01 = depth.at<float>(y0, x0 + 1);
  const float d10 = depth.at<float>(y0 + 1, x0), d11 = depth.at<float>(y0 + 1, x0 + 1);
  if (!(d00 > 0.0f && d01 > 0.0f && d10 > 0.0f && d11 > 0.0f)) return z;
  const float span =
      std::max(std::max(d00, d01), std::max(d10, d11)) - std::min(std::min(d00, d01), std::min(d10, d11));
  if (span > c.depth_discontinuity_ratio * z) return z;  // depth_window_px 0 does not look at them
  const float a = u - float(x0), b = v - float(y0);
  return (1 - b) * ((1 - a) * d00 + a * d01) + b * ((1 - a) * d10 + a * d11);
}

// The depth [m] of a keypoint at the colour instant, read where its surface was when the depth
// image was taken (T_d_c: colour-instant camera to depth-instant camera). The point at depth z on
// the keypoint's ray is T_d_c X(z) at the depth instant; z is the one whose depth-instant point the
// depth image confirms. The pixel shift is mostly rotation and hardly depends on z, so a few
// fixed-point steps from the pure-rotation shift converge. The shift found for the undistorted
// keypoint is applied at its raw pixel (distortion is smooth over a few pixels).
float depth_at_colour_instant(const cv::Mat& depth, const cv::Point2f& raw, const cv::Point2f& und,
                              const PinholeCamera& cam, const SE3& T_d_c, const FeatureConfig& c) {
  const Vec3 ray = T_d_c.linear() * cam.backproject(und.x, und.y, 1.0);
  const Vec3& t = T_d_c.translation();
  if (!(ray.z() > 0.1)) return 0.0f;
  Eigen::Vector2d u_d = cam.project(ray);
  float z_c = 0.0f;
  for (int step = 0; step < 3; ++step) {
    const float z_d =
        keypoint_depth(depth, raw.x + float(u_d.x() - und.x), raw.y + float(u_d.y() - und.y), c);
    if (z_d <= 0.0f) return 0.0f;
    z_c = static_cast<float>((z_d - t.z()) / ray.z());
    if (!(z_c >= c.min_depth_m && z_c <= c.max_depth_m)) return 0.0f;
    u_d = cam.project(ray * double(z_c) + t);
  }
  return z_c;
}

// Sigma of a depth z [m] under the sensor model (DepthNoiseConfig).
float depth_sigma(const DepthNoiseConfig& c, float z) {
  return static_cast<float>(c.sigma0_m + c.k_per_m * double(z) * z);
}

void undistort_keypoints(std::vector<cv::KeyPoint>& kps, const PinholeCamera& cam) {
  if (kps.empty()) return;
  std::vector<cv::Point2f> pts(kps.size());
  for (std::size_t i = 0; i < kps.size(); ++i) pts[i] = kps[i].pt;
  const cv::Matx33d K(cam.fx, 0, cam.cx, 0, cam.fy, cam.cy, 0, 0, 1);
  cv::undistortPoints(pts, pts, K, cv::Mat(cam.dist), cv::noArray(), K);
  for (std::size_t i = 0; i < kps.size(); ++i) kps[i].pt = pts[i];
}

}  // namespace

void DepthNoiseConfig::validate() const {
  require(model == "sensor" || model == "virtual_right",
          "features.depth_noise.model must be 'sensor' or 'virtual_right', got '" + model + "'");
  require(sigma0_m >= 0 && k_per_m >= 0 && sigma0_m + k_per_m > 0,
          "features.depth_noise: need sigma0_m >= 0, k_per_m >= 0, not both 0");
}

void FeatureConfig::validate() const {
  orb.validate();
  depth_noise.validate();
  require(min_depth_m > 0 && max_depth_m > min_depth_m, "features: need 0 < min_depth_m < max_depth_m");
  require(depth_discontinuity_ratio > 0, "features.depth_discontinuity_ratio must be > 0");
  require(depth_window_px >= 0 && depth_window_px <= 10, "features.depth_window_px must be in [0, 10]");
}

void FeatureGrid::build(const std::vector<cv::KeyPoint>& kps, int width, int height, int cell_px) {
  cell_ = cell_px;
  cols_ = (width + cell_ - 1) / cell_;
  rows_ = (height + cell_ - 1) / cell_;
  cells_.assign(static_cast<std::size_t>(cols_) * rows_, {});
  for (int i = 0; i < static_cast<int>(kps.size()); ++i) {
    const int cx = static_cast<int>(std::floor(kps[i].pt.x / cell_));
    const int cy = static_cast<int>(std::floor(kps[i].pt.y / cell_));
    if (cx < 0 || cy < 0 || cx >= cols_ || cy >= rows_) continue;  // undistorted outside the image
    cells_[cy * cols_ + cx].push_back(i);
  }
}

std::vector<int> FeatureGrid::in_area(const std::vector<cv::KeyPoint>& kps, double u, double v, double r,
                                      int min_level, int max_level) const {
  std::vector<int> out;
  const int x0 = std::max(0, static_cast<int>(std::floor((u - r) / cell_)));
  const int x1 = std::min(cols_ - 1, static_cast<int>(std::floor((u + r) / cell_)));
  const int y0 = std::max(0, static_cast<int>(std::floor((v - r) / cell_)));
  const int y1 = std::min(rows_ - 1, static_cast<int>(std::floor((v + r) / cell_)));
  for (int cy = y0; cy <= y1; ++cy)
    for (int cx = x0; cx <= x1; ++cx)
      for (int i : cells_[cy * cols_ + cx]) {
        const auto& k = kps[i];
        if (k.octave < min_level || (max_level >= 0 && k.octave > max_level)) continue;
        if (std::abs(k.pt.x - u) < r && std::abs(k.pt.y - v) < r) out.push_back(i);
      }
  return out;
}

void set_right_coordinates(FrameFeatures& f, double bf) {
  f.u_right.assign(f.keypoints.size(), kNoRight);
  for (std::size_t i = 0; i < f.keypoints.size(); ++i)
    if (f.depth_m[i] > 0.0f) f.u_right[i] = static_cast<float>(f.keypoints[i].pt.x - bf / f.depth_m[i]);
}

std::vector<cv::Point2f> raw_pixels(const FrameFeatures& f, const PinholeCamera& camera) {
  std::vector<cv::Point2f> px(f.keypoints.size());
  for (std::size_t i = 0; i < px.size(); ++i) px[i] = f.keypoints[i].pt;
  if (!camera.has_distortion() || px.empty()) return px;
  // Undistorted pixels back through the lens: normalised rays projected with the distortion.
  std::vector<cv::Point3f> rays(px.size());
  for (std::size_t i = 0; i < px.size(); ++i)
    rays[i] = {float((px[i].x - camera.cx) / camera.fx), float((px[i].y - camera.cy) / camera.fy), 1.0f};
  const cv::Matx33d K(camera.fx, 0, camera.cx, 0, camera.fy, camera.cy, 0, 0, 1);
  cv::projectPoints(rays, cv::Vec3d(0, 0, 0), cv::Vec3d(0, 0, 0), K, cv::Mat(camera.dist), px);
  return px;
}

void read_keypoint_depths(FrameFeatures& f, const std::vector<cv::Point2f>& raw_px, const cv::Mat& depth_m,
                          const PinholeCamera& camera, const FeatureConfig& config,
                          const std::optional<SE3>& T_d_c) {
  require(raw_px.size() == f.keypoints.size(), "read_keypoint_depths: one raw pixel per keypoint");
  f.depth_m.assign(raw_px.size(), 0.0f);
  f.depth_sigma_m.assign(raw_px.size(), 0.0f);
  if (!depth_m.empty())
    for (std::size_t i = 0; i < raw_px.size(); ++i) {
      const float z =
          T_d_c ? depth_at_colour_instant(depth_m, raw_px[i], f.keypoints[i].pt, camera, *T_d_c, config)
                : keypoint_depth(depth_m, raw_px[i].x, raw_px[i].y, config);
      f.depth_m[i] = z;
      if (z > 0 && config.depth_noise.sensor()) f.depth_sigma_m[i] = depth_sigma(config.depth_noise, z);
    }
  set_right_coordinates(f, camera.bf);
}

int drop_masked_keypoints(std::vector<cv::KeyPoint>& keypoints, cv::Mat& descriptors, const cv::Mat& mask) {
  require(mask.type() == CV_8UC1, "drop_masked_keypoints: the mask must be CV_8UC1");
  std::vector<cv::KeyPoint> kept;
  cv::Mat kept_desc;
  kept.reserve(keypoints.size());
  for (std::size_t i = 0; i < keypoints.size(); ++i) {
    const int u = std::clamp(static_cast<int>(keypoints[i].pt.x), 0, mask.cols - 1);
    const int v = std::clamp(static_cast<int>(keypoints[i].pt.y), 0, mask.rows - 1);
    if (mask.at<std::uint8_t>(v, u) != 0) continue;
    kept.push_back(keypoints[i]);
    kept_desc.push_back(descriptors.row(static_cast<int>(i)));
  }
  const int dropped = static_cast<int>(keypoints.size() - kept.size());
  if (dropped == 0) return 0;
  keypoints = std::move(kept);
  descriptors = kept_desc.empty() ? cv::Mat(0, descriptors.cols, descriptors.type()) : kept_desc;
  return dropped;
}

void undo_rolling_shutter(std::vector<cv::KeyPoint>& keypoints, const std::vector<cv::Point2f>& seen,
                          const std::vector<float>& depth_m, const PinholeCamera& camera,
                          const RollingShutter& shutter) {
  if (!shutter.on()) return;
  require(seen.size() == keypoints.size() && (depth_m.empty() || depth_m.size() == keypoints.size()),
          "undo_rolling_shutter: one seen pixel (and depth) per keypoint");
  // The camera that read row v: step^(dt / step_dt_s) with dt = readout_s * v / (height - 1), i.e.
  // se3_power with the step's logarithm taken once for all keypoints.
  const Vec6 log_step = se3_log(shutter.step);
  const int last_row = std::max(1, camera.height - 1);
  for (std::size_t i = 0; i < keypoints.size(); ++i) {
    const double dt = shutter.readout_s * std::clamp(double(seen[i].y), 0.0, double(last_row)) / last_row;
    const double x = dt / shutter.step_dt_s;
    const SE3 T_c_row = (x == 1.0 ? shutter.step : se3_exp(x * log_step)).inverse();
    const Vec3 ray = T_c_row.linear() * camera.backproject(seen[i].x, seen[i].y, 1.0);
    if (!(ray.z() > 0.1)) continue;
    // With depth z at the stamp's camera: the point of the seen ray that lies at that depth.
    const double z = depth_m.empty() ? 0.0 : double(depth_m[i]);
    const Vec3& t = T_c_row.translation();
    const Vec3 p = z > 0 ? Vec3(ray * ((z - t.z()) / ray.z()) + t) : ray;
    if (!(p.z() > 0)) continue;
    const Eigen::Vector2d u = camera.project(p);
    keypoints[i].pt = cv::Point2f(float(u.x()), float(u.y()));
  }
}

FrameFeatures compute_frame_features(const cv::Mat& rgb, const cv::Mat& depth_m, const PinholeCamera& camera,
                                     const OrbExtractor& extractor, const FeatureConfig& config,
                                     const std::optional<SE3>& T_d_c, const cv::Mat& exclude,
                                     const RollingShutter& shutter) {
  require(!rgb.empty() && (rgb.type() == CV_8UC3 || rgb.type() == CV_8UC1),
          "compute_frame_features: expected a CV_8UC3 (BGR) or CV_8UC1 image");
  require(depth_m.empty() || (depth_m.type() == CV_32FC1 && depth_m.size() == rgb.size()),
          "compute_frame_features: depth must be CV_32FC1 metres with the image's size");
  require(exclude.empty() || (exclude.type() == CV_8UC1 && exclude.size() == rgb.size()),
          "compute_frame_features: the exclusion mask must be CV_8UC1 with the image's size");
  FrameFeatures f;
  f.pyramid = extractor.pyramid();
  // 1. ORB on the grey image.
  cv::Mat gray;
  if (rgb.channels() == 3)
    cv::cvtColor(rgb, gray, cv::COLOR_BGR2GRAY);
  else
    gray = rgb;
  std::vector<cv::KeyPoint> raw;
  extractor.extract(gray, raw, f.descriptors);
  if (!exclude.empty()) drop_masked_keypoints(raw, f.descriptors, exclude);
  // 2. Undistort; a rolling shutter's rows back to the stamp's instant.
  f.keypoints = raw;
  if (camera.has_distortion()) undistort_keypoints(f.keypoints, camera);
  std::vector<cv::Point2f> raw_px(raw.size());
  for (std::size_t i = 0; i < raw.size(); ++i) raw_px[i] = raw[i].pt;
  std::vector<cv::Point2f> seen;
  if (shutter.on()) {
    for (const cv::KeyPoint& k : f.keypoints) seen.push_back(k.pt);
    undo_rolling_shutter(f.keypoints, seen, {}, camera, shutter);
    // The depth image is one snapshot: read it where the surface is at the stamp (the shift found
    // for the undistorted keypoint, applied at its raw pixel).
    for (std::size_t i = 0; i < raw_px.size(); ++i) raw_px[i] += f.keypoints[i].pt - seen[i];
  }
  // 3. Depth, its sigma and the virtual right coordinate (with a rolling shutter, the keypoints with
  //    depth moved by the camera's translation too); 4. grid.
  read_keypoint_depths(f, raw_px, depth_m, camera, config, T_d_c);
  if (shutter.on()) {
    undo_rolling_shutter(f.keypoints, seen, f.depth_m, camera, shutter);
    set_right_coordinates(f, camera.bf);
  }
  f.grid.build(f.keypoints, camera.width, camera.height);
  return f;
}

}  // namespace s3m::features
