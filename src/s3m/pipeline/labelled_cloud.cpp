#include "s3m/pipeline/labelled_cloud.hpp"

#include <cmath>
#include <unordered_map>

#include "s3m/core/error.hpp"

namespace s3m::pipeline {

std::size_t LabelledCloud::bytes() const {
  return p_c.size() * sizeof(Eigen::Vector3f) + bgr.size() + ids.size() * sizeof(ClassId) +
         probs.size() * sizeof(float);
}

LabelledCloud backproject(const PinholeCamera& camera, const cv::Mat& depth_m, const cv::Mat& bgr,
                          const semantics::LabelMap& labels, const BackprojectOptions& o) {
  require(depth_m.type() == CV_32FC1, "backproject: depth must be CV_32FC1 metres");
  require(bgr.empty() || (bgr.type() == CV_8UC3 && bgr.size() == depth_m.size()),
          "backproject: colour image must be CV_8UC3 of the depth image's size");
  require(labels.empty() || (labels.rows() == depth_m.rows && labels.cols() == depth_m.cols),
          "backproject: label map must have the depth image's size");
  require(o.pixel_stride >= 1, "backproject: pixel_stride must be >= 1");
  LabelledCloud c;
  c.k = labels.empty() ? 0 : labels.k();
  const auto z_min = static_cast<float>(o.min_depth_m), z_max = static_cast<float>(o.max_depth_m);
  for (int v = 0; v < depth_m.rows; v += o.pixel_stride) {
    const float* d = depth_m.ptr<float>(v);
    for (int u = 0; u < depth_m.cols; u += o.pixel_stride) {
      const float z = d[u];
      if (!(z >= z_min && z <= z_max)) continue;  // also rejects NaN
      c.p_c.push_back(camera.backproject(u, v, z).cast<float>());
      if (!bgr.empty()) {
        const auto& px = bgr.at<cv::Vec3b>(v, u);
        c.bgr.insert(c.bgr.end(), {px[0], px[1], px[2]});
      } else {
        c.bgr.insert(c.bgr.end(), {128, 128, 128});
      }
      for (int j = 0; j < c.k; ++j) {
        c.ids.push_back(labels.id(v, u, j));
        c.probs.push_back(labels.prob(v, u, j));
      }
    }
  }
  return c;
}

LabelledCloud voxel_downsample(const LabelledCloud& in, double voxel_m) {
  if (voxel_m <= 0) return in;
  LabelledCloud out;
  out.k = in.k;
  const double inv = 1.0 / voxel_m;
  std::unordered_map<std::uint64_t, bool> seen;
  seen.reserve(in.size() / 4 + 16);
  for (std::size_t i = 0; i < in.size(); ++i) {
    const Eigen::Vector3f& p = in.p_c[i];
    // 21 bits per axis covers +-10 km at 1 cm; camera clouds are within a few metres.
    auto cell = [&](float x) { return static_cast<std::uint64_t>(std::floor(x * inv) + (1 << 20)) & 0x1FFFFF; };
    const std::uint64_t key = cell(p.x()) | (cell(p.y()) << 21) | (cell(p.z()) << 42);
    if (!seen.emplace(key, true).second) continue;
    out.p_c.push_back(p);
    out.bgr.insert(out.bgr.end(), in.bgr.begin() + 3 * i, in.bgr.begin() + 3 * i + 3);
    out.ids.insert(out.ids.end(), in.ids.begin() + in.k * i, in.ids.begin() + in.k * (i + 1));
    out.probs.insert(out.probs.end(), in.probs.begin() + in.k * i, in.probs.begin() + in.k * (i + 1));
  }
  return out;
}

}  // namespace s3m::pipeline
