#include "s3m/features/orb_extractor.hpp"

#include <algorithm>
#include <cmath>

#include <opencv2/imgproc.hpp>

#include "s3m/core/error.hpp"
#include "s3m/features/keypoint_distribution.hpp"

namespace s3m::features {
namespace {

constexpr int kEdgePx = 19;        // descriptor patch (31 px) half-size plus margin
constexpr int kPatchSize = 31;
constexpr int kHalfPatch = 15;     // radius of the orientation disc

// Intensity-centroid orientation [deg] of the disc around pt (level image coordinates).
float ic_angle_deg(const cv::Mat& img, cv::Point2f pt, const std::vector<int>& umax) {
  const uchar* center = &img.at<uchar>(cvRound(pt.y), cvRound(pt.x));
  const int step = static_cast<int>(img.step1());
  int m01 = 0, m10 = 0;
  for (int u = -kHalfPatch; u <= kHalfPatch; ++u) m10 += u * center[u];
  for (int v = 1; v <= kHalfPatch; ++v) {
    int v_sum = 0;
    const int d = umax[v];
    for (int u = -d; u <= d; ++u) {
      const int val_plus = center[u + v * step], val_minus = center[u - v * step];
      v_sum += (val_plus - val_minus);
      m10 += u * (val_plus + val_minus);
    }
    m01 += v * v_sum;
  }
  return cv::fastAtan2(static_cast<float>(m01), static_cast<float>(m10));
}

}  // namespace

void OrbConfig::validate() const {
  require(n_features > 0, "orb.n_features must be > 0");
  require(scale_factor > 1.0 && scale_factor < 4.0, "orb.scale_factor must be in (1, 4)");
  require(n_levels >= 1 && n_levels <= 16, "orb.n_levels must be in [1, 16]");
  require(min_fast_threshold > 0 && ini_fast_threshold >= min_fast_threshold,
          "orb FAST thresholds: need 0 < min_fast_threshold <= ini_fast_threshold");
  require(cell_px >= 8, "orb.cell_px must be >= 8");
  require(level_sigma_exponent >= 0 && level_sigma_exponent <= 2, "orb.level_sigma_exponent must be in [0, 2]");
}

ScalePyramid ScalePyramid::make(double scale_factor, int n_levels, double sigma_exponent) {
  ScalePyramid p;
  p.scale_factor = scale_factor;
  p.log_scale_factor = std::log(scale_factor);
  p.sigma_exponent = sigma_exponent;
  double s = 1.0;
  for (int l = 0; l < n_levels; ++l, s *= scale_factor) {
    p.scale.push_back(s);
    p.inv_scale.push_back(1.0 / s);
    const double sigma2 = std::pow(s, 2 * sigma_exponent);
    p.sigma2.push_back(sigma2);
    p.inv_sigma2.push_back(1.0 / sigma2);
  }
  return p;
}

OrbExtractor::OrbExtractor(const OrbConfig& config)
    : config_(config), pyramid_(ScalePyramid::make(config.scale_factor, config.n_levels, config.level_sigma_exponent)) {
  config_.validate();
  // Geometric share of the features per level, proportional to the level's image area^(1/2).
  const double f = 1.0 / config_.scale_factor;
  double n_level = config_.n_features * (1.0 - f) / (1.0 - std::pow(f, config_.n_levels));
  int assigned = 0;
  for (int l = 0; l + 1 < config_.n_levels; ++l, n_level *= f) {
    features_per_level_.push_back(static_cast<int>(std::lround(n_level)));
    assigned += features_per_level_.back();
  }
  features_per_level_.push_back(std::max(0, config_.n_features - assigned));

  umax_.resize(kHalfPatch + 1);
  for (int v = 0; v <= kHalfPatch; ++v)
    umax_[v] = static_cast<int>(std::floor(std::sqrt(double(kHalfPatch * kHalfPatch - v * v)) + 0.5));

  for (int l = 0; l < config_.n_levels; ++l)
    orb_.push_back(cv::ORB::create(config_.n_features, 1.2f, 1, kEdgePx, 0, 2, cv::ORB::FAST_SCORE, kPatchSize,
                                   config_.ini_fast_threshold));
}

void OrbExtractor::process_level(const cv::Mat& img, int level, cv::Size2f to_level0, std::vector<cv::KeyPoint>& out,
                                 cv::Mat& desc) const {
  out.clear();
  // 1. FAST with the low threshold over the usable area; the score tells which corners the high
  //    threshold would have found too.
  std::vector<cv::KeyPoint> all;
  cv::FAST(img, all, config_.min_fast_threshold, true);
  const float x0 = kEdgePx, y0 = kEdgePx, x1 = img.cols - kEdgePx, y1 = img.rows - kEdgePx;
  if (x1 <= x0 || y1 <= y0) return;
  // 2. Per cell: use the strong corners when the cell has any, the weak ones otherwise.
  const int cell = config_.cell_px;
  const int ncx = (img.cols + cell - 1) / cell, ncy = (img.rows + cell - 1) / cell;
  std::vector<char> strong(ncx * ncy, 0);
  std::vector<cv::KeyPoint> inside;
  inside.reserve(all.size());
  for (const auto& k : all) {
    if (k.pt.x < x0 || k.pt.y < y0 || k.pt.x >= x1 || k.pt.y >= y1) continue;
    inside.push_back(k);
    if (k.response >= config_.ini_fast_threshold) strong[int(k.pt.y) / cell * ncx + int(k.pt.x) / cell] = 1;
  }
  std::vector<cv::KeyPoint> kept;
  kept.reserve(inside.size());
  for (const auto& k : inside)
    if (!strong[int(k.pt.y) / cell * ncx + int(k.pt.x) / cell] || k.response >= config_.ini_fast_threshold)
      kept.push_back(k);
  // 3. Spread over the image, 4. orientation, 5. rotated BRIEF on the Gaussian-blurred level
  //    (OpenCV, single-level ORB: same blur and pattern as its pyramid path), 6. to level 0.
  out = distribute_quadtree(kept, x0, x1, y0, y1, features_per_level_[level]);
  for (auto& k : out) {
    k.angle = ic_angle_deg(img, k.pt, umax_);
    k.octave = 0;
    k.size = kPatchSize;
  }
  if (out.empty()) return;
  orb_[level]->compute(img, out, desc);  // keeps order; drops only points too close to the border
  // Level pixel centres to level-0 pixels: cv::resize maps pixel centres, x0 + 0.5 = (xl + 0.5) * r,
  // with r the level's actual size ratio per axis (rounded sizes: up to 0.2 % off the nominal
  // scale). The nominal "x0 = xl * scale" put level-7 keypoints ~1.3 px up-left of their corners.
  const float s = static_cast<float>(pyramid_.scale[level]);
  for (auto& k : out) {
    k.octave = level;
    k.size = kPatchSize * s;
    k.pt = {(k.pt.x + 0.5f) * to_level0.width - 0.5f, (k.pt.y + 0.5f) * to_level0.height - 0.5f};
  }
}

void OrbExtractor::extract(const cv::Mat& gray, std::vector<cv::KeyPoint>& keypoints, cv::Mat& descriptors) const {
  require(gray.type() == CV_8UC1 && !gray.empty(), "OrbExtractor::extract: expected a non-empty CV_8UC1 image");
  // 1. Pyramid, each level resized from the previous one like OpenCV's ORB does, so the
  //    descriptor stage sees the same levels.
  const int n = config_.n_levels;
  std::vector<cv::Mat> levels(n);
  levels[0] = gray;
  for (int l = 1; l < n; ++l) {
    const cv::Size sz(cvRound(gray.cols * pyramid_.inv_scale[l]), cvRound(gray.rows * pyramid_.inv_scale[l]));
    cv::resize(levels[l - 1], levels[l], sz, 0, 0, cv::INTER_LINEAR_EXACT);
  }
  // 2. Detection and description per level (independent, so optionally in parallel).
  std::vector<std::vector<cv::KeyPoint>> per_level(n);
  std::vector<cv::Mat> per_level_desc(n);
  auto body = [&](const cv::Range& r) {
    for (int l = r.start; l < r.end; ++l) {
      const cv::Size2f to_level0(float(gray.cols) / levels[l].cols, float(gray.rows) / levels[l].rows);
      process_level(levels[l], l, to_level0, per_level[l], per_level_desc[l]);
    }
  };
  if (config_.parallel_levels)
    cv::parallel_for_(cv::Range(0, n), body);
  else
    body(cv::Range(0, n));
  keypoints.clear();
  std::vector<cv::Mat> descs;
  for (int l = 0; l < n; ++l) {
    keypoints.insert(keypoints.end(), per_level[l].begin(), per_level[l].end());
    if (!per_level[l].empty()) descs.push_back(per_level_desc[l]);
  }
  if (descs.empty())
    descriptors = cv::Mat(0, 32, CV_8U);
  else
    cv::vconcat(descs, descriptors);
}

}  // namespace s3m::features
