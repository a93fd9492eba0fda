#pragma once
// Frame-to-frame dense RGB-D odometry (OpenCV rgbd's RgbdICPOdometry: photometric + point-to-plane
// ICP over an image pyramid) for the frames feature tracking loses. A textured poster leaving the
// view of a turn towards a plain wall leaves ORB with under 100 keypoints while the wall's faint
// texture, the room's corners and the floor still fix the motion densely: on the simulator's
// living-room loop the dense step is within 0.07 deg / 2.5 mm of the truth per frame with sensor
// noise, where the constant-velocity guess drifts 0.1-0.3 deg per frame (docs/RESULTS.md, issue 20).
// A single plane leaves it degenerate, so the caller checks it against its own prediction.
#include <optional>

#include <opencv2/core.hpp>

#include "s3m/core/camera.hpp"
#include "s3m/core/rgbd_frame.hpp"
#include "s3m/core/se3.hpp"

namespace s3m::slam {

struct DepthOdometryConfig {
  int downsample = 2;          // images are shrunk by this factor first (speed; 2: 320x240 from VGA)
  double min_depth_m = 0.1;    // depths outside [min, max] are not used [m]
  double max_depth_m = 6.0;
  double max_depth_diff_m = 0.07;  // ICP correspondences further apart in depth are rejected [m]
  void validate() const;
};

class DepthOdometry {
 public:
  DepthOdometry(const PinholeCamera& camera, const DepthOdometryConfig& config);

  // The motion between two frames, T_cur_prev (maps the previous camera's points into the current
  // camera), searched from T_cur_prev_guess; nullopt when the alignment does not converge. Images
  // are undistorted first when the camera has distortion.
  std::optional<SE3> align(const RgbdFrame& prev, const RgbdFrame& cur, const SE3& T_cur_prev_guess) const;

 private:
  // Grey image (CV_8UC1) and depth (CV_32FC1 metres, NaN = none) at the odometry's resolution.
  void prepare(const RgbdFrame& frame, cv::Mat& grey, cv::Mat& depth) const;

  PinholeCamera camera_;
  DepthOdometryConfig config_;
  cv::Mat K_;                // intrinsics at the odometry's resolution
  cv::Mat map_x_, map_y_;    // undistortion maps at full resolution (empty: no distortion)
};

}  // namespace s3m::slam
