#include "s3m/rosbag2/cdr_writer.hpp"

#include <cmath>
#include <cstdlib>

#include <fmt/format.h>

#include "s3m/core/error.hpp"

namespace s3m::rosbag2 {

void CdrWriter::str(const std::string& s) {
  u32(static_cast<std::uint32_t>(s.size() + 1));
  b_.insert(b_.end(), s.begin(), s.end());
  b_.push_back(0);
}

void CdrWriter::bytes(const std::uint8_t* data, std::size_t n) {
  u32(static_cast<std::uint32_t>(n));
  b_.insert(b_.end(), data, data + n);
}

Stamp stamp_of(double t_s) {
  require(std::isfinite(t_s) && t_s >= 0 && t_s < 2147483647.0,
          "stamp_of: time " + std::to_string(t_s) + " s");
  const std::string text = fmt::format("{:.9f}", t_s);  // the decimal digits Header::stamp_s() reads back
  const std::size_t dot = text.find('.');
  return {static_cast<std::int32_t>(std::stol(text.substr(0, dot))),
          static_cast<std::uint32_t>(std::stoul(text.substr(dot + 1)))};
}

void write_header(CdrWriter& w, Stamp t, const std::string& frame_id) {
  w.i32(t.sec);
  w.u32(t.nanosec);
  w.str(frame_id);
}

void write_pose(CdrWriter& w, const SE3& T) {
  const Quat q(T.rotation());
  for (double v : {T.translation().x(), T.translation().y(), T.translation().z(), q.x(), q.y(), q.z(), q.w()})
    w.f64(v);
}

std::vector<std::uint8_t> encode_image(Stamp t, const std::string& frame_id, const cv::Mat& image) {
  cv::Mat px;
  std::string encoding;
  if (image.type() == CV_8UC3) {
    cv::Mat rgb(image.size(), CV_8UC3);
    for (int v = 0; v < image.rows; ++v)
      for (int u = 0; u < image.cols; ++u) {
        const cv::Vec3b& p = image.at<cv::Vec3b>(v, u);
        rgb.at<cv::Vec3b>(v, u) = {p[2], p[1], p[0]};
      }
    px = rgb, encoding = "rgb8";
  } else if (image.type() == CV_32FC1) {
    px = image.isContinuous() ? image : image.clone(), encoding = "32FC1";
  } else if (image.type() == CV_16UC1) {
    px = image.isContinuous() ? image : image.clone(), encoding = "16UC1";
  } else {
    throw Error("encode_image: image type " + std::to_string(image.type()) +
                " (expected CV_8UC3, CV_32FC1, CV_16UC1)");
  }
  CdrWriter w;
  write_header(w, t, frame_id);
  w.u32(static_cast<std::uint32_t>(px.rows));
  w.u32(static_cast<std::uint32_t>(px.cols));
  w.str(encoding);
  w.u8(0);  // little endian
  w.u32(static_cast<std::uint32_t>(px.cols * px.elemSize()));
  w.bytes(px.data, px.total() * px.elemSize());
  return w.take();
}

std::vector<std::uint8_t> encode_camera_info(Stamp t, const std::string& frame_id, const PinholeCamera& c) {
  CdrWriter w;
  write_header(w, t, frame_id);
  w.u32(static_cast<std::uint32_t>(c.height));
  w.u32(static_cast<std::uint32_t>(c.width));
  w.str("plumb_bob");
  w.u32(5);
  for (double d : c.dist) w.f64(d);
  for (double k : {c.fx, 0.0, c.cx, 0.0, c.fy, c.cy, 0.0, 0.0, 1.0}) w.f64(k);
  for (double r : {1.0, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 1.0}) w.f64(r);
  for (double p : {c.fx, 0.0, c.cx, 0.0, 0.0, c.fy, c.cy, 0.0, 0.0, 0.0, 1.0, 0.0}) w.f64(p);
  for (int i = 0; i < 6; ++i) w.u32(0);  // binning_x, binning_y, roi x, y, height, width
  w.u8(0);                               // roi.do_rectify
  return w.take();
}

std::vector<std::uint8_t> encode_pose_stamped(Stamp t, const std::string& frame_id, const SE3& T) {
  CdrWriter w;
  write_header(w, t, frame_id);
  write_pose(w, T);
  return w.take();
}

std::vector<std::uint8_t> encode_tf_message(Stamp t, const std::string& parent, const std::string& child,
                                            const SE3& T) {
  CdrWriter w;
  w.u32(1);
  write_header(w, t, parent);
  w.str(child);
  write_pose(w, T);
  return w.take();
}

}  // namespace s3m::rosbag2
