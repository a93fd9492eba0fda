#pragma once
// The features of one RGB-D frame as tracking and mapping use them: undistorted ORB keypoints,
// descriptors, depth per keypoint and the virtual right coordinate u_r = u - bf / z that turns a
// depth measurement into a stereo-like observation (ORB-SLAM's RGB-D trick), plus a grid for fast
// "keypoints near (u, v)" queries.
#include <cstdint>
#include <vector>

#include <opencv2/core.hpp>

#include "s3m/core/camera.hpp"
#include "s3m/features/orb_extractor.hpp"

namespace s3m::features {

struct FeatureConfig {
  OrbConfig orb;
  double min_depth_m = 0.1;  // depths outside [min, max] are treated as missing
  double max_depth_m = 6.0;
  // Depth is not trusted where the neighbourhood spans an edge (unregistered depth makes
  // keypoints on object borders pick up the background): reject when max - min over a
  // (2*depth_window_px+1)^2 window exceeds depth_discontinuity_ratio * z.
  double depth_discontinuity_ratio = 0.05;
  int depth_window_px = 2;

  void validate() const;
};

// Uniform grid of keypoint indices over the image (cells of cell_px).
class FeatureGrid {
 public:
  void build(const std::vector<cv::KeyPoint>& kps, int width, int height, int cell_px = 10);
  // Indices of keypoints with |u - ku| < r and |v - kv| < r and level in [min_level, max_level]
  // (max_level < 0: any level).
  std::vector<int> in_area(const std::vector<cv::KeyPoint>& kps, double u, double v, double r, int min_level = 0,
                           int max_level = -1) const;

 private:
  int cell_ = 10, cols_ = 0, rows_ = 0;
  std::vector<std::vector<int>> cells_;
};

struct FrameFeatures {
  std::vector<cv::KeyPoint> keypoints;  // undistorted, level-0 pixels; octave = pyramid level
  cv::Mat descriptors;                  // N x 32 CV_8U
  std::vector<float> depth_m;           // per keypoint; 0 = no (trusted) depth
  std::vector<float> u_right;           // per keypoint [px]; < 0 = no depth
  FeatureGrid grid;
  ScalePyramid pyramid;

  int size() const { return static_cast<int>(keypoints.size()); }
  const std::uint8_t* descriptor(int i) const { return descriptors.ptr<std::uint8_t>(i); }
  bool has_depth(int i) const { return depth_m[i] > 0.0f; }
  std::vector<int> in_area(double u, double v, double r, int min_level = 0, int max_level = -1) const {
    return grid.in_area(keypoints, u, v, r, min_level, max_level);
  }
};

// Extracts ORB from rgb (CV_8UC3 BGR or CV_8UC1), undistorts keypoints when the camera has
// distortion, and reads depth (CV_32F metres, same size; may be empty = no depth) at the raw
// keypoint pixels.
FrameFeatures compute_frame_features(const cv::Mat& rgb, const cv::Mat& depth_m, const PinholeCamera& camera,
                                     const OrbExtractor& extractor, const FeatureConfig& config);

}  // namespace s3m::features
