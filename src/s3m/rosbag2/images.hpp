#pragma once
// ROS 2 image messages as the images an RgbdFrame holds. Each checks the message against its own
// fields (step and size against data, encoding, format) and throws s3m::Error naming `where` and
// what was expected; nothing reads past the message.
#include <string>

#include <opencv2/core.hpp>

#include "s3m/rosbag2/cdr.hpp"

namespace s3m::rosbag2 {

// Colour: rgb8, bgr8, rgba8, bgra8, mono8 -> CV_8UC3 BGR.
cv::Mat colour_image(const Image& m, const std::string& where);
// Depth: 16UC1 / mono16 in depth units (metres_per_unit: 1e-3 for the drivers' millimetres) or
// 32FC1 metres -> CV_32FC1 metres (0 = no measurement).
cv::Mat depth_image(const Image& m, double metres_per_unit, const std::string& where);
// Labels: 16UC1 / mono16 class ids -> CV_16UC1.
cv::Mat label_image(const Image& m, const std::string& where);

// jpeg or png colour (image_transport's "compressed") -> CV_8UC3 BGR.
cv::Mat colour_image(const CompressedImage& m, const std::string& where);
// image_transport's "compressedDepth": a 12-byte header (int32 format, float32 quantisation
// parameters) then a PNG: 16-bit depth units (16UC1) or quantised inverse depth (32FC1) ->
// CV_32FC1 metres.
cv::Mat depth_image(const CompressedImage& m, double metres_per_unit, const std::string& where);

}  // namespace s3m::rosbag2
