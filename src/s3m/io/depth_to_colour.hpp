#pragma once
// Depth from a depth camera beside the colour camera, drawn into the colour camera's pixels: what a
// RealSense's "align to colour" or a Kinect driver's "depth_registered" stream does, for recordings
// that kept the raw depth stream (a RealSense SDK .bag, realsense2_camera's depth/image_rect_raw).
//
// Every depth pixel is a small square patch at its depth: its two opposite corners are moved into
// the colour camera (T_c_d) and projected (with the colour camera's distortion), and the colour
// pixels between them take that depth, the nearest surface winning where several land (so a colour
// image finer than the depth image has no holes between depth samples, and a near object hides the
// background it occludes). Colour pixels no depth pixel reaches stay 0 (no measurement).
//
// Not cv::rgbd::registerDepth: in OpenCV 4.6 it writes past its buffer when the depth image is
// larger than the colour image (opencv_contrib#3761; a RealSense D4xx's 848x480 depth next to a
// 640x480 colour stream is exactly that case) and leaves holes when the colour image is finer.
// Units: metres; poses named as in s3m/core/se3.hpp.
#include <string>
#include <vector>

#include <opencv2/core.hpp>

#include "s3m/core/camera.hpp"
#include "s3m/core/se3.hpp"

namespace s3m::io {

class DepthToColour {
 public:
  // depth: the depth camera (its distortion, if any, is undone once here); colour: the camera the
  // output is for; T_c_d maps depth-camera points into the colour camera. Throws s3m::Error on an
  // invalid camera.
  DepthToColour(const PinholeCamera& depth, const PinholeCamera& colour, const SE3& T_c_d);

  // depth_m: CV_32FC1 metres, the depth camera's size (0 or non-finite = no measurement).
  // Returns CV_32FC1 metres at the colour camera's size. Throws s3m::Error on a size mismatch.
  cv::Mat operator()(const cv::Mat& depth_m) const;

  const PinholeCamera& depth_camera() const { return depth_; }
  const PinholeCamera& colour_camera() const { return colour_; }
  const SE3& T_c_d() const { return T_c_d_; }
  // For logs: "depth camera 848x480 fx 425.0 at (-1.50, 0.03, 0.02) cm in the colour camera; its
  // depth is drawn into the colour camera's 640x480 pixels" (the offset is T_c_d's translation).
  std::string describe() const;

 private:
  // false: outside the field of view the colour camera's distortion model is valid for.
  inline bool to_pixel(const Vec3& p_c, cv::Point2d& px) const;

  PinholeCamera depth_, colour_;
  SE3 T_c_d_;
  bool distorted_ = false;  // the colour camera's
  double max_r2_ = 0;       // with distortion: squared normalised radius beyond which points are dropped
  // The depth image's pixel corners (u-.5, v-.5), u = 0..width, v = 0..height, as rays
  // R_c_d * (x, y, 1): a corner at depth z is then z * ray + t_c_d in the colour camera. Pixel (u, v)
  // spans corners (u, v) and (u+1, v+1).
  std::vector<Vec3> corner_rays_;
};

}  // namespace s3m::io
