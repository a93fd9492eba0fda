#include "s3m/semantics/seg_metrics.hpp"

#include <cmath>
#include <limits>
#include <sstream>

#include <fmt/format.h>
#include <opencv2/imgproc.hpp>

#include "s3m/core/error.hpp"

namespace s3m::semantics {

ConfusionMatrix::ConfusionMatrix(int num_classes) : n_(num_classes), counts_(std::size_t(num_classes) * num_classes, 0) {
  require(num_classes >= 2 && num_classes <= 4096, "ConfusionMatrix: num_classes must be in 2..4096");
}

void ConfusionMatrix::add(const cv::Mat& gt, const cv::Mat& pred) {
  require(gt.type() == CV_16UC1 && pred.type() == CV_16UC1, "ConfusionMatrix::add: expected CV_16UC1 label images");
  require(gt.size() == pred.size(), "ConfusionMatrix::add: ground truth " + std::to_string(gt.cols) + "x" +
                                        std::to_string(gt.rows) + " and prediction " + std::to_string(pred.cols) +
                                        "x" + std::to_string(pred.rows) + " differ in size");
  for (int r = 0; r < gt.rows; ++r) {
    const ClassId* g = gt.ptr<ClassId>(r);
    const ClassId* p = pred.ptr<ClassId>(r);
    for (int c = 0; c < gt.cols; ++c) {
      if (g[c] == cls::kUnknown || g[c] >= n_) continue;
      ++counts_[std::size_t(g[c]) * n_ + (p[c] < n_ ? p[c] : 0)];
    }
  }
}

void ConfusionMatrix::add(const ConfusionMatrix& other) {
  require(other.n_ == n_, "ConfusionMatrix::add: class counts differ");
  for (std::size_t i = 0; i < counts_.size(); ++i) counts_[i] += other.counts_[i];
}

SegMetrics ConfusionMatrix::metrics(const std::vector<ClassId>& exclude) const {
  SegMetrics m;
  m.iou.assign(n_, std::numeric_limits<double>::quiet_NaN());
  m.gt_px.assign(n_, 0);
  std::vector<long long> pred_px(n_, 0);
  long long correct = 0;
  for (int g = 0; g < n_; ++g)
    for (int p = 0; p < n_; ++p) {
      m.gt_px[g] += at(g, p);
      pred_px[p] += at(g, p);
      m.evaluated_px += at(g, p);
      if (g == p) correct += at(g, p);
    }
  double sum = 0;
  for (int c = 1; c < n_; ++c) {  // class 0 = unknown is never a ground-truth class
    const long long uni = m.gt_px[c] + pred_px[c] - at(c, c);
    if (uni > 0) m.iou[c] = double(at(c, c)) / double(uni);
    const bool excluded = std::find(exclude.begin(), exclude.end(), c) != exclude.end();
    if (m.gt_px[c] > 0 && !excluded) {
      sum += m.iou[c];
      m.evaluated.push_back(static_cast<ClassId>(c));
    }
  }
  m.miou = m.evaluated.empty() ? 0.0 : sum / double(m.evaluated.size());
  m.pixel_accuracy = m.evaluated_px ? double(correct) / double(m.evaluated_px) : 0.0;
  return m;
}

cv::Mat ConfusionMatrix::render(const ClassList& classes) const {
  std::vector<int> shown;
  for (int c = 0; c < n_; ++c) {
    long long row = 0, col = 0;
    for (int o = 0; o < n_; ++o) row += at(c, o), col += at(o, c);
    if (row > 0 || col > 0) shown.push_back(c);
  }
  if (shown.empty()) shown.push_back(0);
  const int cell = 44, left = 130, top = 110, n = int(shown.size());
  cv::Mat img(top + n * cell + 40, left + n * cell + 20, CV_8UC3, cv::Scalar(255, 255, 255));
  auto name = [&](int c) { return c < int(classes.size()) ? classes.all()[c].name : std::to_string(c); };
  for (int i = 0; i < n; ++i) {
    long long row = 0;
    for (int o = 0; o < n_; ++o) row += at(shown[i], o);
    for (int j = 0; j < n; ++j) {
      const double f = row > 0 ? double(at(shown[i], shown[j])) / double(row) : 0.0;
      // white -> dark blue ramp; text flips to white on dark cells
      const cv::Scalar colour(255, 255 - 200 * f, 255 - 235 * f);
      const cv::Rect cellr(left + j * cell, top + i * cell, cell, cell);
      cv::rectangle(img, cellr, colour, cv::FILLED);
      cv::rectangle(img, cellr, cv::Scalar(200, 200, 200), 1);
      if (f >= 0.005)
        cv::putText(img, fmt::format("{:.0f}", 100 * f), {cellr.x + 8, cellr.y + 28}, cv::FONT_HERSHEY_SIMPLEX, 0.45,
                    f > 0.5 ? cv::Scalar(255, 255, 255) : cv::Scalar(0, 0, 0), 1, cv::LINE_AA);
    }
    cv::putText(img, name(shown[i]), {6, top + i * cell + 28}, cv::FONT_HERSHEY_SIMPLEX, 0.45, {0, 0, 0}, 1, cv::LINE_AA);
    // column labels written vertically: draw on a rotated strip
    cv::Mat strip(cell, top - 10, CV_8UC3, cv::Scalar(255, 255, 255));
    cv::putText(strip, name(shown[i]), {4, 28}, cv::FONT_HERSHEY_SIMPLEX, 0.45, {0, 0, 0}, 1, cv::LINE_AA);
    cv::Mat rotated;
    cv::rotate(strip, rotated, cv::ROTATE_90_COUNTERCLOCKWISE);
    rotated.copyTo(img(cv::Rect(left + i * cell, 0, cell, top - 10)));
  }
  cv::putText(img, "rows: ground truth, columns: prediction, % of each row", {6, top + n * cell + 26},
              cv::FONT_HERSHEY_SIMPLEX, 0.45, {0, 0, 0}, 1, cv::LINE_AA);
  return img;
}

std::string format_metrics(const SegMetrics& m, const ClassList& classes) {
  std::ostringstream out;
  out << fmt::format("{:<14} {:>8} {:>12}\n", "class", "IoU", "GT pixels");
  for (std::size_t c = 1; c < m.iou.size(); ++c) {
    if (std::isnan(m.iou[c]) && m.gt_px[c] == 0) continue;
    const std::string name = c < classes.size() ? classes.all()[c].name : std::to_string(c);
    out << fmt::format("{:<14} {:>8} {:>12}\n", name, std::isnan(m.iou[c]) ? std::string("-") : fmt::format("{:.3f}", m.iou[c]),
                       m.gt_px[c]);
  }
  out << fmt::format("mIoU {:.4f} over {} classes, pixel accuracy {:.4f} over {} pixels\n", m.miou, m.evaluated.size(),
                     m.pixel_accuracy, m.evaluated_px);
  return out.str();
}

}  // namespace s3m::semantics
