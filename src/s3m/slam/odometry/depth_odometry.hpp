#pragma once
// Frame-to-frame dense RGB-D odometry (OpenCV rgbd's RgbdICPOdometry: photometric + point-to-plane
// ICP over an image pyramid) for the frames feature tracking loses. A textured poster leaving the
// view of a turn towards a plain wall leaves ORB with under 100 keypoints while the wall's faint
// texture, the room's corners and the floor still fix the motion densely, and far better than the
// constant-velocity guess does (see docs/DECISIONS.md, "Tracking: depth odometry across gaps").
// A single plane leaves it degenerate, so the caller checks it against its own prediction, and
// align_observable() measures only what such a view fixes.
#include <optional>

#include <opencv2/core.hpp>
#include <opencv2/rgbd.hpp>

#include "s3m/core/camera.hpp"
#include "s3m/core/rgbd_frame.hpp"
#include "s3m/core/se3.hpp"

namespace s3m::slam {

struct DepthOdometryConfig {
  int downsample = 2;        // images are shrunk by this factor first (speed; 2: 320x240 from VGA)
  double min_depth_m = 0.1;  // depths outside [min, max] are not used [m]
  double max_depth_m = 6.0;
  double max_depth_diff_m = 0.07;  // ICP correspondences further apart in depth are rejected [m]
  // align_observable(): a direction of the motion counts as measured when the points' information
  // along it (eigenvalue of the point-to-plane normal equations, rotations scaled by the median
  // depth so all six are in metres) is at least this fraction of the number of points. A plane
  // seen head-on gives about 1 for its distance, 0.07-0.11 for its two tilts, 0 for the rest; the
  // living-room loop's plain wall with the sofa's back gives 0.016 and 0.0003 for two more.
  double min_observed_ratio = 0.01;
  // How far one align() may move the pose from its start before OpenCV calls it failed: its own
  // defaults, made for consecutive 30 Hz frames. align() multiplies them by its step_scale, so that
  // a frame after a gap (dropped frames, a 2 Hz recording) can move by as much as the gap allows.
  double max_step_m = 0.15;
  double max_step_deg = 15.0;
  // After such a gap (step_scale > 1) the alignment runs twice: first with correspondences up to
  // this far apart in depth, to reach the right basin from a start that far off, then with
  // max_depth_diff_m from there [m].
  double gap_max_depth_diff_m = 0.3;
  void validate() const;
};

// align_observable()'s result: the motion and how much of it the view measured.
struct ObservableMotion {
  SE3 T_cur_prev = SE3::Identity();
  int observed_directions = 0;  // of 6; the rest are the guess's
  int n_points = 0;             // point-to-plane correspondences at the last iteration
  double inlier_fraction = 0;   // n_points over the current frame's points with depth
  double rms_m = 0;             // their point-to-plane residual RMS [m]
};

class DepthOdometry {
 public:
  DepthOdometry(const PinholeCamera& camera, const DepthOdometryConfig& config);

  // The motion between two frames, T_cur_prev (maps the previous camera's points into the current
  // camera), searched from T_cur_prev_guess; nullopt when the alignment does not converge or moves
  // further from the guess than step_scale x (max_step_m, max_step_deg). Images are undistorted
  // first when the camera has distortion.
  std::optional<SE3> align(const RgbdFrame& prev, const RgbdFrame& cur, const SE3& T_cur_prev_guess,
                           double step_scale = 1.0) const;

  // A frame made ready for align(): undistorted, at the odometry's resolution, in OpenCV's frame
  // whose pyramids, normals and masks the first alignment computes and keeps. A keyframe linked to
  // the one before it and then to the one after it is prepared once (about a quarter of an
  // alignment's time; identical results). Shared, not thread-safe: one thread at a time.
  using PreparedFrame = cv::Ptr<cv::rgbd::OdometryFrame>;
  PreparedFrame prepare(const RgbdFrame& frame) const;
  std::optional<SE3> align(const PreparedFrame& prev, const PreparedFrame& cur, const SE3& T_cur_prev_guess,
                           double step_scale = 1.0) const;

  // Point-to-plane ICP (depth only) that moves the guess only along the directions the view
  // constrains: the solution remapping of Zhang, Kaess and Singh, "On degeneracy of
  // optimization-based state estimation problems" (ICRA 2016). A single plane in view fixes its
  // distance and the two tilts and leaves the slide along it and the turn about its normal to the
  // guess (the tracker's constant velocity), where align() fails or slides along the valley.
  // nullopt when fewer than 100 points correspond.
  std::optional<ObservableMotion> align_observable(const RgbdFrame& prev, const RgbdFrame& cur,
                                                   const SE3& T_cur_prev_guess) const;

 private:
  // Depth (CV_32FC1 metres, NaN = none; checks the frame) and grey image (CV_8UC1) at the
  // odometry's resolution, undistorted.
  cv::Mat prepare_depth(const RgbdFrame& frame) const;
  cv::Mat prepare_grey(const RgbdFrame& frame) const;
  std::optional<SE3> compute(const PreparedFrame& prev, const PreparedFrame& cur,
                             const SE3& T_cur_prev_guess) const;

  PinholeCamera camera_;
  DepthOdometryConfig config_;
  cv::Mat K_;  // intrinsics at the odometry's resolution
  // Created once: its normals computer precomputes per-pixel terms on first use (~300 ms at VGA),
  // which a fresh odometry per call paid every time. Not safe to share between threads (its
  // cache is mutable); each thread has its own DepthOdometry.
  cv::Ptr<cv::rgbd::RgbdICPOdometry> odometry_;
  cv::Mat map_x_, map_y_;  // undistortion maps at full resolution (empty: no distortion)
};

// Two estimates of one step (T_cur_last) agree: within max_deg / max_m, or within `fraction` of the
// step's rotation and translation where that is more, but never more than twice max_deg / max_m.
// Estimates of a step across a gap (a sparse recording, dropped frames) differ by a few percent
// of it. Twice the bounds at most, because an alignment can slide into the same wrong basin from
// both sides and then agree with itself closely (see docs/DECISIONS.md, "Tracking: depth odometry
// across gaps"). 30 Hz steps (< 2 deg / 4 cm) keep max_deg / max_m.
bool odometry_steps_agree(const SE3& step, const SE3& other, double max_deg, double max_m, double fraction);

// How well a step T_cur_last explains both views: of the last frame's depth pixels (every 4th row
// and column, metres, 0 / NaN = none) that it moves in front of `camera` onto a measured depth of
// the current frame, the fraction within 3 cm or 3 % of that depth; 0 when none lands. Both depth
// images in `camera`'s pixels. Right steps score clearly higher than wrong ones, but where one plane
// fills the view a slide along it scores ~1 too, so it can only choose between estimates, not
// confirm one (see docs/DECISIONS.md, "Tracking: depth odometry across gaps").
double depth_agreement(const PinholeCamera& camera, const cv::Mat& depth_last, const cv::Mat& depth_cur,
                       const SE3& T_cur_last);

// How well a step T_cur_last explains both colour images: the zero-mean normalised cross-correlation
// (in [-1, 1]) of grey levels between the last frame's pixels with depth (every 4th row and column)
// and where the step puts them in the current frame (bilinear), over those that land on a current
// depth within 3 cm or 3 % (seen by both). Depth alone cannot tell a box-like room from the same
// room seen the other way round; its textures can (see docs/DECISIONS.md, "Tracking: colour
// agreement"). Invariant to gain and offset, so auto exposure does not count against a step.
// nullopt when fewer than 100 pixels land or either side has no contrast (a black image).
std::optional<double> colour_agreement(const PinholeCamera& camera, const RgbdFrame& last,
                                       const RgbdFrame& cur, const SE3& T_cur_last);

}  // namespace s3m::slam
