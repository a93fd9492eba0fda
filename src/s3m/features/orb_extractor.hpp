#pragma once
// ORB features with a scale pyramid and spatially distributed keypoints (ORB-SLAM style):
// FAST corners per pyramid level with a two-threshold fallback per cell, a quadtree that keeps the
// strongest corner per node so features cover the image, intensity-centroid orientation, and
// rotated-BRIEF descriptors computed by OpenCV's ORB on our keypoints.
#include <vector>

#include <opencv2/core.hpp>
#include <opencv2/features2d.hpp>

namespace s3m::features {

struct OrbConfig {
  int n_features = 1000;        // total over all levels
  double scale_factor = 1.2;    // between consecutive pyramid levels
  int n_levels = 8;
  // Keypoint position sigma of level l = scale_factor^(l * level_sigma_exponent) px (ScalePyramid).
  // ORB-SLAM's 1 (sigma = the level's scale) over-states how much worse coarse levels are: the
  // residuals measured per level grow like an exponent of 0.5-0.8 (see docs/DECISIONS.md,
  // "Keypoint sigma per pyramid level").
  double level_sigma_exponent = 0.75;
  int ini_fast_threshold = 20;  // FAST threshold tried first in each cell [grey levels]
  int min_fast_threshold = 7;   // fallback for low-contrast cells
  int cell_px = 30;             // cell size of the threshold fallback
  bool parallel_levels = true;  // detect pyramid levels concurrently (TBB through cv::parallel_for_)

  void validate() const;
};

// Scale of every pyramid level (level 0 = 1) and the keypoint position variance per level used as
// measurement information in the optimisers: sigma of a level-l keypoint = scale[l]^sigma_exponent
// px (1 = ORB-SLAM's sigma = scale).
struct ScalePyramid {
  std::vector<double> scale, inv_scale, sigma2, inv_sigma2;
  double scale_factor = 1.2;
  double log_scale_factor = 0.0;
  double sigma_exponent = 1.0;

  static ScalePyramid make(double scale_factor, int n_levels, double sigma_exponent);
  int n_levels() const { return static_cast<int>(scale.size()); }
};

class OrbExtractor {
 public:
  explicit OrbExtractor(const OrbConfig& config);

  // gray: CV_8UC1. Keypoints are in level-0 pixel coordinates with octave = level,
  // angle in degrees, size = 31 * level scale. descriptors: N x 32 CV_8U, row i for keypoint i.
  void extract(const cv::Mat& gray, std::vector<cv::KeyPoint>& keypoints, cv::Mat& descriptors) const;

  const ScalePyramid& pyramid() const { return pyramid_; }
  const OrbConfig& config() const { return config_; }

 private:
  // Keypoints of one level with their descriptors, in level-0 pixels; to_level0 = level-0 size /
  // this level's size per axis.
  void process_level(const cv::Mat& level_img, int level, cv::Size2f to_level0, std::vector<cv::KeyPoint>& kps,
                     cv::Mat& desc) const;

  OrbConfig config_;
  ScalePyramid pyramid_;
  std::vector<int> features_per_level_;
  std::vector<int> umax_;  // half-width of the orientation disc per row
  std::vector<cv::Ptr<cv::ORB>> orb_;  // descriptor computation only, one single-level ORB per level
};

}  // namespace s3m::features
