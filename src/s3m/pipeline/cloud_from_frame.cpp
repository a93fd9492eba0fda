#include "s3m/pipeline/cloud_from_frame.hpp"

#include <cmath>
#include <unordered_set>

#include "s3m/core/error.hpp"

namespace s3m::pipeline {

mapping::LabeledCloud backproject(const PinholeCamera& camera, const cv::Mat& depth_m, const cv::Mat& bgr,
                                  const semantics::LabelMap& labels, const BackprojectOptions& o) {
  require(depth_m.type() == CV_32FC1, "backproject: depth must be CV_32FC1 metres");
  require(bgr.empty() || (bgr.type() == CV_8UC3 && bgr.size() == depth_m.size()),
          "backproject: colour image must be CV_8UC3 of the depth image's size");
  require(labels.empty() || (labels.rows() == depth_m.rows && labels.cols() == depth_m.cols),
          "backproject: label map must have the depth image's size");
  require(o.pixel_stride >= 1, "backproject: pixel_stride must be >= 1");
  mapping::LabeledCloud c;
  c.k = labels.empty() ? 0 : labels.k();
  c.reserve(static_cast<std::size_t>(depth_m.total() / (o.pixel_stride * o.pixel_stride)));
  const auto z_min = static_cast<float>(o.min_depth_m), z_max = static_cast<float>(o.max_depth_m);
  for (int v = 0; v < depth_m.rows; v += o.pixel_stride) {
    const float* d = depth_m.ptr<float>(v);
    for (int u = 0; u < depth_m.cols; u += o.pixel_stride) {
      const float z = d[u];
      if (!(z >= z_min && z <= z_max)) continue;  // also rejects NaN
      const cv::Vec3b px = bgr.empty() ? cv::Vec3b(128, 128, 128) : bgr.at<cv::Vec3b>(v, u);
      const ClassId* ids = c.k ? labels.ids.ptr<ClassId>(v) + u * c.k : nullptr;
      const float* probs = c.k ? labels.probs.ptr<float>(v) + u * c.k : nullptr;
      c.push_back(camera.backproject(u, v, z).cast<float>(), px[2], px[1], px[0], ids, probs);
    }
  }
  return c;
}

mapping::LabeledCloud voxel_downsample(const mapping::LabeledCloud& in, double voxel_m) {
  if (voxel_m <= 0) return in;
  mapping::LabeledCloud out;
  out.k = in.k;
  out.origin = in.origin;
  const double inv = 1.0 / voxel_m;
  std::unordered_set<std::uint64_t> seen;
  seen.reserve(in.size() / 4 + 16);
  // 21 bits per axis: +-10 km at 1 cm voxels; camera clouds span a few metres.
  auto cell = [&](float x) { return static_cast<std::uint64_t>(std::floor(x * inv) + (1 << 20)) & 0x1FFFFF; };
  const bool has_rgb = !in.rgb.empty();
  for (std::size_t i = 0; i < in.size(); ++i) {
    const Eigen::Vector3f& p = in.points[i];
    if (!seen.insert(cell(p.x()) | (cell(p.y()) << 21) | (cell(p.z()) << 42)).second) continue;
    const std::uint8_t* rgb = has_rgb ? &in.rgb[3 * i] : nullptr;
    out.push_back(p, rgb ? rgb[0] : 128, rgb ? rgb[1] : 128, rgb ? rgb[2] : 128,
                  in.k ? &in.labels[in.k * i] : nullptr, in.k ? &in.probs[in.k * i] : nullptr);
  }
  if (!has_rgb) out.rgb.clear();
  return out;
}

mapping::LabeledCloud transformed(const mapping::LabeledCloud& in, const SE3& T_a_b) {
  mapping::LabeledCloud out = in;
  const Eigen::Isometry3f T = T_a_b.cast<float>();
  for (auto& p : out.points) p = T * p;
  out.origin = T * in.origin;
  return out;
}

std::size_t cloud_bytes(const mapping::LabeledCloud& c) {
  return c.points.capacity() * sizeof(Eigen::Vector3f) + c.rgb.capacity() + c.labels.capacity() * sizeof(ClassId) +
         c.probs.capacity() * sizeof(float);
}

}  // namespace s3m::pipeline
