#include "s3m/pipeline/reprojection.hpp"

#include <algorithm>

#include "s3m/core/error.hpp"
#include "s3m/mapping/queries.hpp"

namespace s3m::pipeline {

EvalFrameSampler::EvalFrameSampler(int every_n, std::size_t max_frames)
    : every_n_(static_cast<std::size_t>(std::max(every_n, 1))), max_frames_(max_frames) {}

bool EvalFrameSampler::wants(std::size_t offered_count) const {
  return max_frames_ > 0 && offered_count % every_n_ == 0;
}

void EvalFrameSampler::keep(EvalFrame f, std::size_t offered_count) {
  frames_.push_back(std::move(f));
  offered_at_.push_back(offered_count);
  if (frames_.size() <= max_frames_) return;
  // Full: keep the frames whose offer count is a multiple of 2n (every other one), double n.
  std::vector<EvalFrame> kept;
  std::vector<std::size_t> at;
  for (std::size_t i = 0; i < frames_.size(); ++i) {
    if (offered_at_[i] % (2 * every_n_) != 0) continue;
    kept.push_back(std::move(frames_[i]));
    at.push_back(offered_at_[i]);
  }
  frames_.swap(kept);
  offered_at_.swap(at);
  every_n_ *= 2;
}

namespace {

// Label of the occupied labelled voxel at p_w, or one voxel closer / farther along the ray.
ClassId map_label(const mapping::SemanticOcTree& map, const Eigen::Vector3d& p_w, const Eigen::Vector3d& step_w) {
  for (const Eigen::Vector3d& q : {p_w, Eigen::Vector3d(p_w - step_w), Eigen::Vector3d(p_w + step_w)})
    if (const auto v = mapping::class_at(map, q)) return v->label;
  return cls::kUnknown;
}

}  // namespace

void add_reprojection(const mapping::SemanticOcTree& map, const PinholeCamera& camera, const ReprojectionInput& in,
                      const ReprojectionOptions& o, ReprojectionScore& score) {
  require(in.depth_m.type() == CV_32FC1 && in.gt_labels.type() == CV_16UC1 && in.frame_pred.type() == CV_16UC1,
          "reprojection: depth must be CV_32FC1 and labels CV_16UC1");
  require(in.gt_labels.size() == in.depth_m.size() && in.frame_pred.size() == in.depth_m.size(),
          "reprojection: depth, ground-truth labels and prediction must have the same size");
  require(o.pixel_stride >= 1, "reprojection: pixel_stride must be >= 1");
  const double res = map.getResolution();
  const Eigen::Vector3d origin_w = in.T_w_c.translation();
  // Gathered into 1-row images so ConfusionMatrix applies its own rules (unknown GT not evaluated).
  std::vector<std::uint16_t> gt, map_pred, frame_pred;
  for (int v = 0; v < in.depth_m.rows; v += o.pixel_stride) {
    const float* d = in.depth_m.ptr<float>(v);
    const std::uint16_t* g = in.gt_labels.ptr<std::uint16_t>(v);
    const std::uint16_t* f = in.frame_pred.ptr<std::uint16_t>(v);
    for (int u = 0; u < in.depth_m.cols; u += o.pixel_stride) {
      if (g[u] == cls::kUnknown || g[u] >= cls::kCount) continue;
      if (!(d[u] >= o.min_depth_m && d[u] <= o.max_depth_m)) continue;  // also rejects NaN
      ++score.evaluated_px;
      const Eigen::Vector3d p_w = in.T_w_c * camera.backproject(u, v, d[u]);
      const ClassId m = map_label(map, p_w, res * (p_w - origin_w).normalized());
      if (m == cls::kUnknown) continue;
      ++score.covered_px;
      gt.push_back(g[u]);
      map_pred.push_back(m);
      frame_pred.push_back(f[u]);
    }
  }
  ++score.frames;
  if (gt.empty()) return;
  const int n = static_cast<int>(gt.size());
  score.map.add(cv::Mat(1, n, CV_16UC1, gt.data()), cv::Mat(1, n, CV_16UC1, map_pred.data()));
  score.frame.add(cv::Mat(1, n, CV_16UC1, gt.data()), cv::Mat(1, n, CV_16UC1, frame_pred.data()));
}

cv::Mat project_map_labels(const mapping::SemanticOcTree& map, const PinholeCamera& camera, const cv::Mat& depth_m,
                           const SE3& T_w_c, const ReprojectionOptions& o) {
  require(depth_m.type() == CV_32FC1, "project_map_labels: depth must be CV_32FC1");
  require(o.pixel_stride >= 1, "project_map_labels: pixel_stride must be >= 1");
  cv::Mat labels(depth_m.size(), CV_16UC1, cv::Scalar(cls::kUnknown));
  const double res = map.getResolution();
  const Eigen::Vector3d origin_w = T_w_c.translation();
  const int s = o.pixel_stride;
  for (int v = 0; v < depth_m.rows; v += s) {
    const float* d = depth_m.ptr<float>(v);
    for (int u = 0; u < depth_m.cols; u += s) {
      if (!(d[u] >= o.min_depth_m && d[u] <= o.max_depth_m)) continue;
      const Eigen::Vector3d p_w = T_w_c * camera.backproject(u, v, d[u]);
      const ClassId m = map_label(map, p_w, res * (p_w - origin_w).normalized());
      if (m != cls::kUnknown) labels(cv::Rect(u, v, std::min(s, depth_m.cols - u), std::min(s, depth_m.rows - v))) = m;
    }
  }
  return labels;
}

}  // namespace s3m::pipeline
