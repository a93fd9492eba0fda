#include "s3m/io/image_io.hpp"

#include <cmath>

#include <fmt/format.h>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include "s3m/core/error.hpp"
#include "s3m/io/atomic_file.hpp"
#include "s3m/io/image_header.hpp"

namespace s3m::io {
namespace {

std::string describe(const cv::Mat& m) {
  const char* depth_names[] = {"8-bit unsigned", "8-bit signed", "16-bit unsigned", "16-bit signed",
                               "32-bit int", "32-bit float", "64-bit float", "16-bit float"};
  return fmt::format("{} {}-channel {}x{}", depth_names[m.depth()], m.channels(), m.cols, m.rows);
}

cv::Mat read_any(const std::string& path, int flags, const std::string& what) {
  check_image_header(path, what);  // refuses non-regular files before opening them
  cv::Mat img;
  try {
    img = cv::imread(path, flags);
  } catch (const cv::Exception& e) {
    throw ParseError(path, 0, std::string("cannot decode image: ") + e.what(), what);
  }
  if (img.empty()) throw ParseError(path, 0, "cannot read or decode image", what);
  return img;
}

void check_size(const cv::Mat& img, cv::Size expected, const std::string& path) {
  if (expected.area() == 0 || img.size() == expected) return;
  throw ParseError(path, 0, fmt::format("image is {}x{}", img.cols, img.rows),
                   fmt::format("{}x{} as given by the camera", expected.width, expected.height));
}

void write_png(const std::string& path, const cv::Mat& img) {
  std::vector<unsigned char> bytes;
  // Compression 1: these files are written per frame; speed matters more than a few percent size.
  if (!cv::imencode(".png", img, bytes, {cv::IMWRITE_PNG_COMPRESSION, 1}))
    throw Error("cannot encode PNG for '" + path + "'");
  write_bytes_atomic(path, bytes);
}

}  // namespace

cv::Mat read_depth_png(const std::string& path, double depth_factor, cv::Size expected) {
  require(std::isfinite(depth_factor) && depth_factor > 0, "read_depth_png: depth_factor must be > 0");
  const std::string what = "a 16-bit single-channel depth PNG";
  const cv::Mat raw = read_any(path, cv::IMREAD_UNCHANGED, what);
  if (raw.depth() != CV_16U || raw.channels() != 1)
    throw ParseError(path, 0, "depth image is " + describe(raw) + (raw.depth() == CV_8U ? " (8-bit depth loses range)" : ""),
                     what);
  check_size(raw, expected, path);
  cv::Mat depth_m;
  raw.convertTo(depth_m, CV_32F, 1.0 / depth_factor);
  return depth_m;
}

void write_depth_png(const std::string& path, const cv::Mat& depth_m, double depth_factor) {
  require(std::isfinite(depth_factor) && depth_factor > 0, "write_depth_png: depth_factor must be > 0");
  require(depth_m.channels() == 1 && (depth_m.depth() == CV_32F || depth_m.depth() == CV_64F),
          "write_depth_png('" + path + "'): expected a CV_32FC1/CV_64FC1 depth image in metres, got " + describe(depth_m));
  cv::Mat d;
  depth_m.convertTo(d, CV_64F);
  cv::Mat raw(d.size(), CV_16UC1);
  for (int v = 0; v < d.rows; ++v) {
    const double* src = d.ptr<double>(v);
    auto* dst = raw.ptr<std::uint16_t>(v);
    for (int u = 0; u < d.cols; ++u) {
      const double x = src[u] * depth_factor;
      dst[u] = (std::isfinite(x) && x > 0) ? static_cast<std::uint16_t>(std::min(65535.0, std::round(x))) : 0;
    }
  }
  write_png(path, raw);
}

cv::Mat read_label_png(const std::string& path, cv::Size expected) {
  const std::string what = "a single-channel 8- or 16-bit label PNG of class ids";
  const cv::Mat raw = read_any(path, cv::IMREAD_UNCHANGED, what);
  if (raw.channels() != 1 || (raw.depth() != CV_8U && raw.depth() != CV_16U))
    throw ParseError(path, 0, "label image is " + describe(raw), what);
  check_size(raw, expected, path);
  cv::Mat labels;
  raw.convertTo(labels, CV_16U);
  return labels;
}

void write_label_png(const std::string& path, const cv::Mat& labels16) {
  require(labels16.channels() == 1 && (labels16.depth() == CV_16U || labels16.depth() == CV_8U),
          "write_label_png('" + path + "'): expected CV_16UC1 class ids, got " + describe(labels16));
  cv::Mat l;
  labels16.convertTo(l, CV_16U);
  write_png(path, l);
}

cv::Mat read_rgb(const std::string& path, cv::Size expected) {
  const std::string what = "an 8-bit colour image";
  cv::Mat raw = read_any(path, cv::IMREAD_UNCHANGED, what);
  if (raw.depth() != CV_8U) throw ParseError(path, 0, "colour image is " + describe(raw), what);
  check_size(raw, expected, path);
  cv::Mat bgr;
  if (raw.channels() == 1) cv::cvtColor(raw, bgr, cv::COLOR_GRAY2BGR);
  else if (raw.channels() == 4) cv::cvtColor(raw, bgr, cv::COLOR_BGRA2BGR);
  else bgr = raw;
  return bgr;
}

void write_rgb_png(const std::string& path, const cv::Mat& bgr8) {
  require(bgr8.type() == CV_8UC3, "write_rgb_png('" + path + "'): expected CV_8UC3 BGR, got " + describe(bgr8));
  write_png(path, bgr8);
}

}  // namespace s3m::io
