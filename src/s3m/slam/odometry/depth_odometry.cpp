#include "s3m/slam/odometry/depth_odometry.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <string>
#include <vector>

#include <opencv2/calib3d.hpp>
#include <opencv2/imgproc.hpp>
#include <opencv2/rgbd.hpp>

#include "s3m/core/error.hpp"

namespace s3m::slam {
namespace {

// The grey image of a BGR (or BGRA, or already grey) colour image.
cv::Mat grey_of(const cv::Mat& image) {
  if (image.channels() == 1) return image;
  cv::Mat grey;
  cv::cvtColor(image, grey, image.channels() == 4 ? cv::COLOR_BGRA2GRAY : cv::COLOR_BGR2GRAY);
  return grey;
}

}  // namespace

void DepthOdometryConfig::validate() const {
  require(downsample >= 1 && downsample <= 8, "tracker.odometry_downsample must be in [1, 8]");
  require(min_depth_m > 0 && max_depth_m > min_depth_m && max_depth_diff_m > 0,
          "tracker odometry: need 0 < min depth < max depth and a positive depth difference");
  require(min_observed_ratio > 0 && min_observed_ratio < 1,
          "tracker.odometry_min_observed_ratio must be in (0, 1)");
  require(max_step_m > 0 && max_step_deg > 0, "tracker odometry: max_step_m and max_step_deg must be > 0");
  require(gap_max_depth_diff_m >= max_depth_diff_m,
          "tracker.odometry_gap_max_depth_diff_m must be >= odometry_max_depth_diff_m");
}

DepthOdometry::DepthOdometry(const PinholeCamera& camera, const DepthOdometryConfig& config)
    : camera_(camera), config_(config) {
  camera_.validate();
  config_.validate();
  const double s = 1.0 / config_.downsample;
  // Pixel centres: (u + 0.5) * s - 0.5 keeps the principal point on the same scene ray.
  K_ = (cv::Mat_<float>(3, 3) << camera_.fx * s, 0, (camera_.cx + 0.5) * s - 0.5, 0, camera_.fy * s,
        (camera_.cy + 0.5) * s - 0.5, 0, 0, 1);
  if (camera_.has_distortion()) {
    const cv::Mat K =
        (cv::Mat_<double>(3, 3) << camera_.fx, 0, camera_.cx, 0, camera_.fy, camera_.cy, 0, 0, 1);
    const cv::Mat dist(1, 5, CV_64F, const_cast<double*>(camera_.dist.data()));
    cv::initUndistortRectifyMap(K, dist, cv::Mat(), K, cv::Size(camera_.width, camera_.height), CV_32FC1,
                                map_x_, map_y_);
  }
  // Per pyramid level, finest first; 0.25 of the pixels with a usable gradient or normal.
  odometry_ = cv::rgbd::RgbdICPOdometry::create(K_, float(config_.min_depth_m), float(config_.max_depth_m),
                                                float(config_.max_depth_diff_m), 0.25f,
                                                std::vector<int>{7, 7, 7, 10});
}

cv::Mat DepthOdometry::prepare_depth(const RgbdFrame& frame) const {
  require(!frame.rgb.empty() && !frame.depth_m.empty() && frame.rgb.size() == frame.depth_m.size(),
          "DepthOdometry: frame " + std::to_string(frame.index) + " needs colour and depth of one size");
  cv::Mat depth = frame.depth_m;
  if (!map_x_.empty())
    cv::remap(depth, depth, map_x_, map_y_, cv::INTER_NEAREST);  // never blend two surfaces' depths
  if (config_.downsample > 1) {
    const double s = 1.0 / config_.downsample;
    cv::resize(depth, depth, cv::Size(), s, s, cv::INTER_NEAREST);
  } else {
    depth = depth.clone();
  }
  // OpenCV's odometry reads missing depth as NaN (0 would be a point on the camera centre).
  depth.setTo(std::numeric_limits<float>::quiet_NaN(),
              (depth < config_.min_depth_m) | (depth > config_.max_depth_m));
  return depth;
}

cv::Mat DepthOdometry::prepare_grey(const RgbdFrame& frame) const {
  cv::Mat grey = grey_of(frame.rgb);
  if (!map_x_.empty()) cv::remap(grey, grey, map_x_, map_y_, cv::INTER_LINEAR);
  if (config_.downsample > 1) {
    const double s = 1.0 / config_.downsample;
    cv::resize(grey, grey, cv::Size(), s, s, cv::INTER_AREA);
  }
  return grey;
}

DepthOdometry::PreparedFrame DepthOdometry::prepare(const RgbdFrame& frame) const {
  return cv::rgbd::OdometryFrame::create(prepare_grey(frame), prepare_depth(frame));
}

std::optional<SE3> DepthOdometry::align(const RgbdFrame& prev, const RgbdFrame& cur,
                                        const SE3& T_cur_prev_guess, double step_scale) const {
  return align(prepare(prev), prepare(cur), T_cur_prev_guess, step_scale);
}

std::optional<SE3> DepthOdometry::align(const PreparedFrame& prev, const PreparedFrame& cur,
                                        const SE3& T_cur_prev_guess, double step_scale) const {
  require(step_scale >= 1.0, "DepthOdometry::align: step_scale must be >= 1");
  odometry_->setMaxTranslation(config_.max_step_m * step_scale);
  odometry_->setMaxRotation(config_.max_step_deg * step_scale);
  if (step_scale == 1.0) return compute(prev, cur, T_cur_prev_guess);
  // After a gap the start is further off than the depth gate lets correspondences form (from no
  // motion, a 17 deg / 20 cm step failed or converged 10-17 deg off on the TUM fr3 cabinet
  // keyframes): the basin with a wide gate first, then the usual alignment from there.
  odometry_->setMaxDepthDiff(config_.gap_max_depth_diff_m);
  const std::optional<SE3> coarse = compute(prev, cur, T_cur_prev_guess);
  odometry_->setMaxDepthDiff(config_.max_depth_diff_m);
  if (!coarse) return std::nullopt;
  return compute(prev, cur, *coarse);
}

std::optional<SE3> DepthOdometry::compute(const PreparedFrame& prev, const PreparedFrame& cur,
                                          const SE3& T_cur_prev_guess) const {
  // OpenCV's Rt maps the source frame's points into the destination's: T_cur_prev.
  cv::Mat init(4, 4, CV_64F), Rt;
  for (int r = 0; r < 4; ++r)
    for (int c = 0; c < 4; ++c) init.at<double>(r, c) = T_cur_prev_guess.matrix()(r, c);
  PreparedFrame src = prev, dst = cur;  // compute() takes the pointers by reference
  if (!odometry_->compute(src, dst, Rt, init)) return std::nullopt;
  Eigen::Matrix4d M;
  for (int r = 0; r < 4; ++r)
    for (int c = 0; c < 4; ++c) M(r, c) = Rt.at<double>(r, c);
  return orthonormalized(SE3(M));
}

bool odometry_steps_agree(const SE3& step, const SE3& other, double max_deg, double max_m, double fraction) {
  constexpr double kMaxWidening = 2.0;
  const double step_deg = rotation_angle_rad(step.linear()) * 180.0 / M_PI;
  return poses_agree(step, other, std::clamp(fraction * step_deg, max_deg, kMaxWidening * max_deg),
                     std::clamp(fraction * step.translation().norm(), max_m, kMaxWidening * max_m));
}

namespace {
// The sampling depth_agreement and colour_agreement share: for each of the last frame's depth
// pixels (u, v) (every 4th row and column) that T_cur_last moves in front of the camera onto a
// measured depth of the current frame (nearest pixel, both in `camera`'s pixels), calls
// visit(u, v, q, agrees): q where it lands, agrees when that depth is within 3 cm or 3 % of its own.
template <class Visit>
void for_each_landing(const PinholeCamera& camera, const cv::Mat& depth_last, const cv::Mat& depth_cur,
                      const SE3& T_cur_last, Visit&& visit) {
  constexpr int kStride = 4;
  for (int v = 0; v < depth_last.rows; v += kStride)
    for (int u = 0; u < depth_last.cols; u += kStride) {
      const float z = depth_last.at<float>(v, u);
      if (!(z > 0.0f)) continue;  // NaN too
      const Vec3 p = T_cur_last * camera.backproject(u, v, z);
      if (p.z() <= 0.0) continue;
      const Eigen::Vector2d q = camera.project(p);
      const long qu = std::lround(q.x()), qv = std::lround(q.y());
      if (qu < 0 || qv < 0 || qu >= depth_cur.cols || qv >= depth_cur.rows) continue;
      const float z_cur = depth_cur.at<float>(static_cast<int>(qv), static_cast<int>(qu));
      if (!(z_cur > 0.0f)) continue;
      visit(u, v, q, std::abs(z_cur - p.z()) <= std::max(0.03, 0.03 * p.z()));
    }
}

// Bilinear grey level at (x, y) of a CV_8UC1 image, with 0 <= x < cols - 1, 0 <= y < rows - 1.
double bilinear(const cv::Mat& grey, double x, double y) {
  const int x0 = static_cast<int>(x), y0 = static_cast<int>(y);
  const double ax = x - x0, ay = y - y0;
  const auto at = [&](int r, int c) { return static_cast<double>(grey.at<std::uint8_t>(r, c)); };
  return (1 - ay) * ((1 - ax) * at(y0, x0) + ax * at(y0, x0 + 1)) +
         ay * ((1 - ax) * at(y0 + 1, x0) + ax * at(y0 + 1, x0 + 1));
}

}  // namespace

double depth_agreement(const PinholeCamera& camera, const cv::Mat& depth_last, const cv::Mat& depth_cur,
                       const SE3& T_cur_last) {
  require(depth_last.type() == CV_32FC1 && depth_cur.type() == CV_32FC1,
          "depth_agreement: depth images must be CV_32FC1");
  int landed = 0, agreeing = 0;
  for_each_landing(camera, depth_last, depth_cur, T_cur_last,
                   [&](int, int, const Eigen::Vector2d&, bool agrees) {
                     ++landed;
                     agreeing += agrees;
                   });
  return landed ? static_cast<double>(agreeing) / landed : 0.0;
}

std::optional<double> colour_agreement(const PinholeCamera& camera, const RgbdFrame& last,
                                       const RgbdFrame& cur, const SE3& T_cur_last) {
  for (const RgbdFrame* f : {&last, &cur})
    require(!f->rgb.empty() && f->rgb.depth() == CV_8U && f->depth_m.type() == CV_32FC1 &&
                f->rgb.size() == f->depth_m.size(),
            "colour_agreement: frame " + std::to_string(f->index) +
                " needs 8-bit colour and CV_32FC1 depth of one size");
  constexpr int kMinPairs = 100;
  const cv::Mat grey_last = grey_of(last.rgb), grey_cur = grey_of(cur.rgb);
  double sa = 0, sb = 0, saa = 0, sbb = 0, sab = 0;
  int n = 0;
  for_each_landing(
      camera, last.depth_m, cur.depth_m, T_cur_last,
      [&](int u, int v, const Eigen::Vector2d& q, bool agrees) {
        // Seen by both, and inside the border bilinear() needs.
        if (!agrees || !(q.x() >= 0 && q.y() >= 0 && q.x() < grey_cur.cols - 1 && q.y() < grey_cur.rows - 1))
          return;
        const double a = grey_last.at<std::uint8_t>(v, u), b = bilinear(grey_cur, q.x(), q.y());
        sa += a, sb += b, saa += a * a, sbb += b * b, sab += a * b;
        ++n;
      });
  if (n < kMinPairs) return std::nullopt;
  const double var_a = saa - sa * sa / n, var_b = sbb - sb * sb / n;
  if (var_a <= 1e-9 * n || var_b <= 1e-9 * n) return std::nullopt;
  return (sab - sa * sb / n) / std::sqrt(var_a * var_b);
}

}  // namespace s3m::slam
