#pragma once
// The features of one RGB-D frame as tracking and mapping use them: undistorted ORB keypoints,
// descriptors, depth per keypoint and the virtual right coordinate u_r = u - bf / z that turns a
// depth measurement into a stereo-like observation (ORB-SLAM's RGB-D trick), plus a grid for fast
// "keypoints near (u, v)" queries.
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include <opencv2/core.hpp>

#include "s3m/core/camera.hpp"
#include "s3m/core/se3.hpp"
#include "s3m/features/orb_extractor.hpp"

namespace s3m::features {

// How far a keypoint's depth is trusted: the sigma of its depth row in tracking and bundle
// adjustment (see docs/DECISIONS.md, "Depth noise model").
struct DepthNoiseConfig {
  // "sensor": each keypoint's depth gets sigma_z = sigma0_m + k_per_m z^2 (structured light and active
  // stereo measure disparity, so the error grows with z^2; Kinect v1 about 1.5e-3 z^2, Khoshelham &
  // Elberink 2012).
  // "virtual_right": ORB-SLAM's weighting through u_r = u - bf / z with the keypoint's pixel sigma,
  // i.e. sigma_z ~ z^2 * level scale / bf (10 cm at 2 m for bf 40): depth hardly counts, and local
  // BA then shrinks the motion even on exact depth.
  std::string model = "sensor";
  double sigma0_m = 0.001;  // sensor noise at z = 0 [m]
  double k_per_m = 0.0015;  // sensor noise growth [1/m]
  bool sensor() const { return model == "sensor"; }
  void validate() const;
};

struct FeatureConfig {
  OrbConfig orb;
  DepthNoiseConfig depth_noise;
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
  std::vector<int> in_area(const std::vector<cv::KeyPoint>& kps, double u, double v, double r,
                           int min_level = 0, int max_level = -1) const;

 private:
  int cell_ = 10, cols_ = 0, rows_ = 0;
  std::vector<std::vector<int>> cells_;
};

// The virtual right coordinate u - bf / z of a keypoint without depth. A real one can be negative:
// a keypoint closer to the left border than bf / z pixels (40 px at 1 m, 80 px at 0.5 m with the
// default bf) has u - bf / z < 0, so "no depth" is a value no keypoint can reach (see
// docs/DECISIONS.md, "Keypoint depth: the no-depth marker").
inline constexpr float kNoRight = -1e9f;
inline bool has_right(double u_right) { return u_right > -1e8; }

struct FrameFeatures {
  std::vector<cv::KeyPoint> keypoints;  // undistorted, level-0 pixels; octave = pyramid level
  cv::Mat descriptors;                  // N x 32 CV_8U
  std::vector<float> depth_m;           // per keypoint; 0 = no (trusted) depth
  std::vector<float> u_right;           // per keypoint [px]; kNoRight = no depth (has_right())
  // Per keypoint: sigma of depth_m [m] (DepthNoiseConfig "sensor"); 0 = no depth, or the depth is
  // weighted through u_right ("virtual_right").
  std::vector<float> depth_sigma_m;
  FeatureGrid grid;
  ScalePyramid pyramid;

  int size() const { return static_cast<int>(keypoints.size()); }
  const std::uint8_t* descriptor(int i) const { return descriptors.ptr<std::uint8_t>(i); }
  bool has_depth(int i) const { return depth_m[i] > 0.0f; }
  // 1 / sigma^2 of the inverse depth 1 / z of keypoint i [m^2] (sigma_rho = sigma_z / z^2), or 0 when
  // its depth is weighted through the virtual right coordinate (or it has none).
  double inverse_depth_info(int i) const {
    const double z = depth_m[i], s = depth_sigma_m[i];
    return (z > 0 && s > 0) ? (z * z) * (z * z) / (s * s) : 0.0;
  }
  std::vector<int> in_area(double u, double v, double r, int min_level = 0, int max_level = -1) const {
    return grid.in_area(keypoints, u, v, r, min_level, max_level);
  }
};

// Fills f.u_right from f's keypoints and depths: u - bf / z [px], kNoRight without depth. The one
// rule, for extraction and for maps loaded from disk.
void set_right_coordinates(FrameFeatures& f, double bf);

// Reads each keypoint's depth at its raw (distorted) pixel raw_px[i], where the depth image is
// sampled (with T_d_c, see compute_frame_features: where its surface was at the depth instant), and
// sets its sigma and virtual right coordinate. Depth: CV_32F metres or empty (no depth).
void read_keypoint_depths(FrameFeatures& f, const std::vector<cv::Point2f>& raw_px, const cv::Mat& depth_m,
                          const PinholeCamera& camera, const FeatureConfig& config,
                          const std::optional<SE3>& T_d_c = std::nullopt);
// f's undistorted keypoints back at their raw (distorted) pixels.
std::vector<cv::Point2f> raw_pixels(const FrameFeatures& f, const PinholeCamera& camera);

// A rolling shutter: raw image row v is read readout_s * v / (height - 1) after the frame's stamp
// (the stamp is the first row's instant). step is the camera's motion over one frame period
// step_dt_s (T_cur_prev, the motion model's guess); the camera dt seconds after the stamp is
// step^(dt / step_dt_s). readout_s 0 = a global shutter.
struct RollingShutter {
  double readout_s = 0.0;
  SE3 step = SE3::Identity();
  double step_dt_s = 0.0;
  bool on() const { return readout_s > 0.0 && step_dt_s > 0.0; }
};

// Moves each keypoint from where its row's camera saw it (seen[i], undistorted) to where the camera
// at the stamp would have: the full motion for keypoints with depth (depth_m[i] > 0, the depth at
// the stamp's camera), a turn for the others (depth_m empty: all; at hand-held speeds the turn
// dominates the readout's skew). Rows are taken from seen (a lens moves a row by a few pixels, a
// fraction of a millisecond).
void undo_rolling_shutter(std::vector<cv::KeyPoint>& keypoints, const std::vector<cv::Point2f>& seen,
                          const std::vector<float>& depth_m, const PinholeCamera& camera,
                          const RollingShutter& shutter);

// Extracts ORB from rgb (CV_8UC3 BGR or CV_8UC1), undistorts keypoints when the camera has
// distortion, and reads depth (CV_32F metres, same size; may be empty = no depth) at the raw
// keypoint pixels.
// T_d_c: where the camera was when the depth image was taken, relative to the colour image's
// instant (maps colour-instant camera points into the depth-instant camera). Given, each keypoint's
// depth is read where its surface was at the depth instant and returned at the colour instant;
// without it (synchronised images) at the keypoint's own pixel.
// exclude (CV_8UC1 of the image's size, or empty): keypoints on its non-zero pixels are dropped
// (things that move: the pose and the map must not use them).
// shutter (on()): keypoints are returned where the camera at the stamp saw them
// (undo_rolling_shutter), and their depth is read there.
FrameFeatures compute_frame_features(const cv::Mat& rgb, const cv::Mat& depth_m, const PinholeCamera& camera,
                                     const OrbExtractor& extractor, const FeatureConfig& config,
                                     const std::optional<SE3>& T_d_c = std::nullopt,
                                     const cv::Mat& exclude = cv::Mat(), const RollingShutter& shutter = {});

// Drops the keypoints (and their descriptor rows) that lie on non-zero pixels of mask (CV_8UC1);
// returns how many were dropped.
int drop_masked_keypoints(std::vector<cv::KeyPoint>& keypoints, cv::Mat& descriptors, const cv::Mat& mask);

}  // namespace s3m::features
