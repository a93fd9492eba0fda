#pragma once
// Image files with the checks a dataset reader needs: each function throws ParseError(path, 0, ...)
// saying what was found and what was expected (unreadable/missing file, 8-bit depth, wrong size).
// expected = {} (0x0) skips the size check. Writers are atomic and create no directories.
#include <string>

#include <opencv2/core.hpp>

namespace s3m::io {

// 16-bit single-channel PNG -> CV_32FC1 metres (value / depth_factor); 0 stays 0 (= no measurement).
cv::Mat read_depth_png(const std::string& path, double depth_factor, cv::Size expected = {});
// CV_32FC1 or CV_64FC1 metres -> 16-bit PNG of round(d * depth_factor), clamped to 65535;
// NaN, Inf and d <= 0 become 0 (no measurement).
void write_depth_png(const std::string& path, const cv::Mat& depth_m, double depth_factor);

// Class-id image: 8- or 16-bit single channel -> CV_16UC1.
cv::Mat read_label_png(const std::string& path, cv::Size expected = {});
void write_label_png(const std::string& path, const cv::Mat& labels16);  // CV_16UC1 (or CV_8UC1)

// Colour image (PNG or JPEG, see image_header.hpp) -> CV_8UC3 BGR. Grey images are expanded to
// 3 channels.
cv::Mat read_rgb(const std::string& path, cv::Size expected = {});
void write_rgb_png(const std::string& path, const cv::Mat& bgr8);  // CV_8UC3

}  // namespace s3m::io
