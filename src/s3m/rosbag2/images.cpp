#include "s3m/rosbag2/images.hpp"

#include <cstring>

#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

namespace s3m::rosbag2 {
namespace {

int channels_of(const std::string& e) {
  if (e == "rgb8" || e == "bgr8") return 3;
  if (e == "rgba8" || e == "bgra8") return 4;
  if (e == "mono8") return 1;
  return 0;
}

// The message's pixels as a cv::Mat of `type` (a copy: the message buffer does not outlive the call).
cv::Mat pixels(const Image& m, int type, const std::string& where) {
  if (m.big_endian && CV_ELEM_SIZE1(type) > 1)
    throw Error(where + ": big-endian " + m.encoding + " image (expected is_bigendian 0)");
  const std::size_t row = static_cast<std::size_t>(m.width) * CV_ELEM_SIZE(type);
  if (m.width == 0 || m.height == 0 || m.step < row ||
      m.data.size != static_cast<std::size_t>(m.step) * m.height)
    throw Error(where + ": " + m.encoding + " image " + std::to_string(m.width) + "x" +
                std::to_string(m.height) + " with step " + std::to_string(m.step) + " and " +
                std::to_string(m.data.size) + " data bytes (expected step >= " + std::to_string(row) +
                " and step x height data bytes)");
  cv::Mat out(static_cast<int>(m.height), static_cast<int>(m.width), type);
  for (int v = 0; v < out.rows; ++v)
    std::memcpy(out.ptr(v), m.data.data + static_cast<std::size_t>(v) * m.step, row);
  return out;
}

cv::Mat decode(const CompressedImage& m, int flags, const std::string& what, const std::string& where) {
  if (m.data.size == 0) throw Error(where + ": empty " + what + " (expected image data)");
  const cv::Mat buf(1, static_cast<int>(m.data.size), CV_8UC1, const_cast<std::uint8_t*>(m.data.data));
  cv::Mat img;
  try {
    img = cv::imdecode(buf, flags);
  } catch (const cv::Exception& e) {
    throw Error(where + ": " + what + " does not decode: " + e.what());
  }
  if (img.empty()) throw Error(where + ": " + what + " (format '" + m.format + "') does not decode");
  return img;
}

}  // namespace

cv::Mat colour_image(const Image& m, const std::string& where) {
  const int n = channels_of(m.encoding);
  if (n == 0)
    throw Error(where + ": colour encoding '" + m.encoding +
                "' (expected rgb8, bgr8, rgba8, bgra8 or mono8)");
  const cv::Mat px = pixels(m, CV_8UC(n), where);
  if (m.encoding == "bgr8") return px;
  cv::Mat bgr;
  const int code = m.encoding == "rgb8"    ? cv::COLOR_RGB2BGR
                   : m.encoding == "rgba8" ? cv::COLOR_RGBA2BGR
                   : m.encoding == "bgra8" ? cv::COLOR_BGRA2BGR
                                           : cv::COLOR_GRAY2BGR;
  cv::cvtColor(px, bgr, code);
  return bgr;
}

cv::Mat depth_image(const Image& m, double metres_per_unit, const std::string& where) {
  if (m.encoding == "32FC1") return pixels(m, CV_32FC1, where);
  if (m.encoding != "16UC1" && m.encoding != "mono16")
    throw Error(where + ": depth encoding '" + m.encoding +
                "' (expected 16UC1 / mono16 in depth units or 32FC1 in metres)");
  cv::Mat depth_m;
  pixels(m, CV_16UC1, where).convertTo(depth_m, CV_32F, metres_per_unit);  // 0 stays "no measurement"
  return depth_m;
}

cv::Mat label_image(const Image& m, const std::string& where) {
  if (m.encoding != "16UC1" && m.encoding != "mono16")
    throw Error(where + ": label encoding '" + m.encoding + "' (expected 16UC1 / mono16 class ids)");
  return pixels(m, CV_16UC1, where);
}

cv::Mat colour_image(const CompressedImage& m, const std::string& where) {
  if (m.format.find("compressedDepth") != std::string::npos)
    throw Error(where + ": format '" + m.format + "' is depth (expected a jpeg or png colour image)");
  cv::Mat img = decode(m, cv::IMREAD_COLOR, "compressed colour image", where);
  return img;
}

cv::Mat depth_image(const CompressedImage& m, double metres_per_unit, const std::string& where) {
  const std::string& f = m.format;
  const bool is_float = f.rfind("32FC1", 0) == 0;
  if (f.find("compressedDepth") == std::string::npos ||
      (!is_float && f.rfind("16UC1", 0) != 0 && f.rfind("mono16", 0) != 0))
    throw Error(where + ": compressed depth format '" + f +
                "' (expected \"16UC1; compressedDepth png\" or \"32FC1; compressedDepth png\")");
  if (f.find("rvl") != std::string::npos)
    throw Error(where + ": compressedDepth rvl (expected png: image_transport's png_level/format png)");
  ByteReader r(m.data, where);
  const auto format = r.le<std::int32_t>("compressedDepth header format");
  const auto quant_a = r.le<float>("compressedDepth header depthQuantA");
  const auto quant_b = r.le<float>("compressedDepth header depthQuantB");
  (void)format;
  CompressedImage png = m;
  png.data = r.take(r.left(), "compressedDepth png");
  const cv::Mat raw = decode(png, cv::IMREAD_UNCHANGED, "compressedDepth png", where);
  if (raw.type() != CV_16UC1) throw Error(where + ": compressedDepth png is not 16-bit single channel");
  cv::Mat depth_m;
  if (!is_float) {
    raw.convertTo(depth_m, CV_32F, metres_per_unit);
    return depth_m;
  }
  // image_transport stores 32FC1 as inverse depth: q = quant_a / z + quant_b (0 = none).
  depth_m.create(raw.size(), CV_32FC1);
  for (int v = 0; v < raw.rows; ++v)
    for (int u = 0; u < raw.cols; ++u) {
      const std::uint16_t q = raw.at<std::uint16_t>(v, u);
      depth_m.at<float>(v, u) = q == 0 ? 0.0f : quant_a / (static_cast<float>(q) - quant_b);
    }
  return depth_m;
}

}  // namespace s3m::rosbag2
