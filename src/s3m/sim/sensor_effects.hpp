#pragma once
// The parts of the sensor model that make real RGB-D cameras lie beyond noise (see sensor.hpp):
// structured-light depth artefacts and the geometry of time-shifted, misregistered captures.
// Free functions on images and poses, so that tests can check each one by hand.
#include <functional>
#include <vector>

#include <opencv2/core.hpp>

#include "s3m/core/se3.hpp"

namespace s3m::sim {

// Structured light matches a window of the projected pattern: near a depth discontinuity the
// window is dominated by the nearer surface, so the foreground grows into the background. Every
// valid pixel within px pixels (a square window) of a nearer pixel whose depth is smaller by more
// than jump_rel of its own takes that nearer depth. depth_m: CV_32FC1 [m], 0 = no depth (kept).
void fatten_edges(cv::Mat& depth_m, int px, double jump_rel);

// Depth from disparity d = fx b / z [px], measured in steps of step_px: z becomes
// fx b / (round(d / step_px) step_px); a disparity that rounds to 0 is beyond range (0 = no depth).
// fx_b_px_m = fx [px] * baseline [m].
void quantise_disparity(cv::Mat& depth_m, double fx_b_px_m, double step_px);

// T_c_d: the depth camera in the colour camera frame when its image is error_px off along u
// (a rotation about the camera y axis by atan(error_px / fx); positive: content moves right).
SE3 misregistered_depth_camera(double error_px, double fx);

// One pose per image row for a rolling shutter: row r at t_first_s + readout_s * r / (rows - 1).
std::vector<SE3> rolling_shutter_poses(const std::function<SE3(double)>& T_w_c_at, double t_first_s,
                                       double readout_s, int rows);

}  // namespace s3m::sim
