#include "s3m/pipeline/dynamic_mask.hpp"

#include <algorithm>

#include <opencv2/imgproc.hpp>

#include "s3m/core/error.hpp"

namespace s3m::pipeline {

DynamicMasker::DynamicMasker(const PinholeCamera& camera, std::vector<ClassId> classes, int margin_px)
    : camera_(camera), classes_(std::move(classes)), margin_px_(margin_px) {
  require(margin_px_ >= 0, "DynamicMasker: margin must be >= 0 px");
}

void DynamicMasker::set_reference(const cv::Mat& argmax, const cv::Mat& depth_m, const SE3& T_w_c) {
  require(argmax.type() == CV_16UC1 && depth_m.type() == CV_32FC1 && argmax.size() == depth_m.size(),
          "DynamicMasker::set_reference: expected CV_16UC1 classes and CV_32FC1 depth of one size");
  auto ref = std::make_shared<Reference>();
  ref->T_w_c = T_w_c;
  for (int v = 0; v < argmax.rows; v += kStride) {
    const auto* cls = argmax.ptr<std::uint16_t>(v);
    const float* z = depth_m.ptr<float>(v);
    for (int u = 0; u < argmax.cols; u += kStride) {
      if (std::find(classes_.begin(), classes_.end(), cls[u]) == classes_.end()) continue;
      if (z[u] > 0 && std::isfinite(z[u]))
        ref->p_c.emplace_back(static_cast<float>((u - camera_.cx) / camera_.fx * z[u]),
                              static_cast<float>((v - camera_.cy) / camera_.fy * z[u]), z[u]);
      else
        ref->no_depth.emplace_back(u, v);
    }
  }
  std::lock_guard lock(mutex_);
  reference_ = std::move(ref);
}

cv::Mat DynamicMasker::mask(const SE3& T_w_c) const {
  std::shared_ptr<const Reference> ref;
  {
    std::lock_guard lock(mutex_);
    ref = reference_;
  }
  if (!ref || (ref->p_c.empty() && ref->no_depth.empty())) return {};
  cv::Mat out = cv::Mat::zeros(camera_.height, camera_.width, CV_8UC1);
  const Eigen::Matrix3f R = (T_w_c.inverse() * ref->T_w_c).linear().cast<float>();
  const Eigen::Vector3f t = (T_w_c.inverse() * ref->T_w_c).translation().cast<float>();
  for (const Eigen::Vector3f& p : ref->p_c) {
    const Eigen::Vector3f q = R * p + t;
    if (q.z() <= 0.05f) continue;
    const int u = static_cast<int>(std::lround(camera_.fx * q.x() / q.z() + camera_.cx));
    const int v = static_cast<int>(std::lround(camera_.fy * q.y() / q.z() + camera_.cy));
    if (u >= 0 && v >= 0 && u < out.cols && v < out.rows) out.at<std::uint8_t>(v, u) = 255;
  }
  for (const cv::Point& p : ref->no_depth) out.at<std::uint8_t>(p) = 255;
  // Close the sampling gaps and grow by the margin: a rectangle is separable, hence cheap.
  const int r = margin_px_ + kStride;
  cv::dilate(out, out, cv::getStructuringElement(cv::MORPH_RECT, {2 * r + 1, 2 * r + 1}));
  return out;
}

cv::Mat label_mask(const cv::Mat& class_ids, const std::vector<ClassId>& classes, int margin_px) {
  require(class_ids.type() == CV_16UC1, "label_mask: expected a CV_16UC1 class image");
  cv::Mat out = cv::Mat::zeros(class_ids.size(), CV_8UC1);
  for (const ClassId c : classes) out.setTo(255, class_ids == c);
  if (margin_px > 0)
    cv::dilate(out, out, cv::getStructuringElement(cv::MORPH_RECT, {2 * margin_px + 1, 2 * margin_px + 1}));
  return out;
}

semantics::LabelMap grow_dynamic_labels(const semantics::LabelMap& labels,
                                        const std::vector<ClassId>& classes, int margin_px,
                                        const cv::Mat& also_dynamic) {
  if (labels.empty() || classes.empty()) return labels;
  require(
      also_dynamic.empty() || (also_dynamic.type() == CV_8UC1 && also_dynamic.size() == labels.argmax.size()),
      "grow_dynamic_labels: the extra mask must be CV_8UC1 of the labels' size");
  // Dynamic class id per pixel (0 elsewhere), spread by a max filter.
  cv::Mat dynamic = cv::Mat::zeros(labels.argmax.size(), CV_16UC1);
  int n = 0;
  for (int v = 0; v < dynamic.rows; ++v) {
    const auto* a = labels.argmax.ptr<std::uint16_t>(v);
    auto* d = dynamic.ptr<std::uint16_t>(v);
    for (int u = 0; u < dynamic.cols; ++u)
      if (std::find(classes.begin(), classes.end(), a[u]) != classes.end()) d[u] = a[u], ++n;
  }
  if (margin_px > 0 && n > 0)
    cv::dilate(dynamic, dynamic,
               cv::getStructuringElement(cv::MORPH_RECT, {2 * margin_px + 1, 2 * margin_px + 1}));
  if (!also_dynamic.empty()) {
    cv::Mat extra = (also_dynamic != 0) & (dynamic == 0);
    n += cv::countNonZero(extra);
    dynamic.setTo(classes.front(), extra);
  }
  if (n == 0) return labels;
  semantics::LabelMap out{labels.ids.clone(), labels.probs.clone(), labels.argmax.clone()};
  const int k = out.k();
  for (int v = 0; v < dynamic.rows; ++v) {
    const auto* d = dynamic.ptr<std::uint16_t>(v);
    auto* ids = out.ids.ptr<ClassId>(v);
    auto* probs = out.probs.ptr<float>(v);
    auto* a = out.argmax.ptr<std::uint16_t>(v);
    for (int u = 0; u < dynamic.cols; ++u) {
      if (d[u] == 0 || a[u] == d[u]) continue;
      for (int j = 0; j < k; ++j)
        ids[u * k + j] = j == 0 ? d[u] : ClassId(0), probs[u * k + j] = j == 0 ? 1.0f : 0.0f;
      a[u] = d[u];
    }
  }
  return out;
}

SE3 predict_pose(const SE3& T_w_prev, const SE3& T_w_last) {
  return T_w_last * (T_w_prev.inverse() * T_w_last);
}

}  // namespace s3m::pipeline
