#include "s3m/semantics/label_map.hpp"

#include <opencv2/imgproc.hpp>

#include "s3m/core/error.hpp"

namespace s3m::semantics {

LabelMap make_label_map(int rows, int cols, int k) {
  require(rows > 0 && cols > 0 && k >= 1 && k <= CV_CN_MAX, "make_label_map: bad size or k");
  LabelMap m;
  m.ids = cv::Mat(rows, cols, CV_16UC(k), cv::Scalar::all(0));
  m.probs = cv::Mat(rows, cols, CV_32FC(k), cv::Scalar::all(0));
  m.argmax = cv::Mat(rows, cols, CV_16UC1, cv::Scalar(0));
  return m;
}

void softmax_planes(std::vector<cv::Mat>& planes) {
  if (planes.empty()) return;
  // Whole-plane OpenCV ops (vectorised) rather than a per-pixel loop over channels.
  cv::Mat max_val = planes[0].clone();
  for (std::size_t i = 1; i < planes.size(); ++i) cv::max(max_val, planes[i], max_val);
  cv::Mat sum(max_val.size(), CV_32FC1, cv::Scalar(0));
  for (auto& p : planes) {
    cv::subtract(p, max_val, p);
    cv::exp(p, p);
    sum += p;
  }
  cv::Mat inv;
  cv::divide(1.0, sum, inv);
  for (auto& p : planes) cv::multiply(p, inv, p);
}

LabelMap topk_from_planes(const std::vector<cv::Mat>& planes, const std::vector<ClassId>& plane_ids, int k) {
  require(!planes.empty(), "topk_from_planes: no planes");
  require(planes.size() == plane_ids.size(), "topk_from_planes: planes and plane_ids differ in length");
  const int rows = planes[0].rows, cols = planes[0].cols;
  for (const auto& p : planes)
    require(p.type() == CV_32FC1 && p.rows == rows && p.cols == cols, "topk_from_planes: planes must be CV_32FC1 of one size");
  LabelMap out = make_label_map(rows, cols, k);
  // Row buffers, rank-major (best[j * cols + x]); each plane is pushed through the k ranks with
  // branch-free compare/select loops over x, which the compiler vectorises. A strict ">" keeps the
  // earlier plane first on ties. ~10x faster than a per-pixel insertion sort at 640x480.
  std::vector<float> best(std::size_t(k) * cols), carry(cols);
  std::vector<std::int32_t> best_id(std::size_t(k) * cols), carry_id(cols);
  for (int r = 0; r < rows; ++r) {
    std::fill(best.begin(), best.end(), -1.f);
    std::fill(best_id.begin(), best_id.end(), 0);
    for (std::size_t i = 0; i < planes.size(); ++i) {
      const float* src = planes[i].ptr<float>(r);
      std::copy(src, src + cols, carry.begin());
      std::fill(carry_id.begin(), carry_id.end(), static_cast<std::int32_t>(plane_ids[i]));
      for (int j = 0; j < k; ++j) {
        float* b = best.data() + std::size_t(j) * cols;
        std::int32_t* bi = best_id.data() + std::size_t(j) * cols;
        float* cv = carry.data();
        std::int32_t* ci = carry_id.data();
        for (int x = 0; x < cols; ++x) {
          const bool gt = cv[x] > b[x];
          const float lo = gt ? b[x] : cv[x], hi = gt ? cv[x] : b[x];
          const std::int32_t lo_i = gt ? bi[x] : ci[x], hi_i = gt ? ci[x] : bi[x];
          b[x] = hi, bi[x] = hi_i, cv[x] = lo, ci[x] = lo_i;
        }
      }
    }
    ClassId* ids = out.ids.ptr<ClassId>(r);
    float* probs = out.probs.ptr<float>(r);
    ClassId* am = out.argmax.ptr<ClassId>(r);
    for (int j = 0; j < k; ++j) {
      const float* b = best.data() + std::size_t(j) * cols;
      const std::int32_t* bi = best_id.data() + std::size_t(j) * cols;
      for (int x = 0; x < cols; ++x) {
        const bool empty = b[x] < 0.f;  // fewer planes than k
        ids[x * k + j] = empty ? ClassId{0} : static_cast<ClassId>(bi[x]);
        probs[x * k + j] = empty ? 0.f : b[x];
      }
    }
    for (int x = 0; x < cols; ++x) am[x] = ids[x * k];
  }
  return out;
}

cv::Mat colorize(const cv::Mat& ids16, const ClassList& classes) {
  require(ids16.type() == CV_16UC1, "colorize: expected a CV_16UC1 class-id image");
  cv::Mat out(ids16.size(), CV_8UC3);
  for (int r = 0; r < ids16.rows; ++r) {
    const ClassId* in = ids16.ptr<ClassId>(r);
    auto* o = out.ptr<cv::Vec3b>(r);
    for (int c = 0; c < ids16.cols; ++c) {
      if (in[c] < classes.size()) {
        const auto& ci = classes.all()[in[c]];
        o[c] = cv::Vec3b(ci.b, ci.g, ci.r);
      } else {
        o[c] = cv::Vec3b(255, 0, 255);
      }
    }
  }
  return out;
}

cv::Mat overlay(const cv::Mat& bgr, const cv::Mat& ids16, const ClassList& classes, double alpha) {
  require(bgr.type() == CV_8UC3 && bgr.size() == ids16.size(), "overlay: image and labels must be CV_8UC3/CV_16UC1 of one size");
  cv::Mat out;
  cv::addWeighted(bgr, 1.0 - alpha, colorize(ids16, classes), alpha, 0.0, out);
  return out;
}

}  // namespace s3m::semantics
