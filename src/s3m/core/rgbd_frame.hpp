#pragma once
// One RGB-D observation as it flows through the system.
#include <opencv2/core.hpp>

namespace s3m {

struct RgbdFrame {
  int index = 0;     // position in the sequence (0-based)
  double t_s = 0.0;  // timestamp [s] of the colour image
  cv::Mat rgb;       // CV_8UC3, BGR channel order (OpenCV convention)
  cv::Mat depth_m;   // CV_32FC1, metres; 0 or NaN = no measurement
  cv::Mat labels;    // optional CV_16UC1 ground-truth class ids (simulator); empty when unknown
  // Optional CV_8UC1, non-zero where the pixel sees something that moves: the simulator's ground
  // truth when it renders people, or what the pipeline predicts for tracking (dynamic_mask.hpp).
  // Tracking uses no keypoint on it. Empty: nothing known to move.
  cv::Mat dynamic_mask;
  // When the depth image was taken relative to the colour image [s] (t_depth - t_s; a recording's
  // associations give it). Unsynchronised cameras pair images up to half a frame apart: at fast
  // rotation the depth then belongs to another view than the colour.
  double depth_dt_s = 0.0;
};

}  // namespace s3m
