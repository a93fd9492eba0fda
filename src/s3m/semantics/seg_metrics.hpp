#pragma once
// Segmentation metrics: confusion matrix, per-class IoU, mIoU, pixel accuracy, and a heat-map image.
// Used by `s3m segeval` and by the pipeline's reports (single-frame and fused-map mIoU).
#include <string>
#include <vector>

#include <opencv2/core.hpp>

#include "s3m/core/classes.hpp"

namespace s3m::semantics {

struct SegMetrics {
  std::vector<double> iou;         // per class; NaN where the class is in neither GT nor prediction
  std::vector<long long> gt_px;    // ground-truth pixels per class
  double miou = 0;                 // mean IoU over evaluated classes with gt_px > 0
  double pixel_accuracy = 0;       // correct / evaluated pixels
  long long evaluated_px = 0;
  std::vector<ClassId> evaluated;  // classes that entered the mIoU
};

class ConfusionMatrix {
 public:
  explicit ConfusionMatrix(int num_classes);

  // Accumulates one image pair (CV_16UC1 project ids, same size). Ground-truth "unknown" (id 0) and
  // ids >= num_classes in the ground truth are not evaluated; predicted ids out of range count as
  // class 0 ("unknown" = no prediction, always wrong).
  void add(const cv::Mat& gt, const cv::Mat& pred);
  void add(const ConfusionMatrix& other);

  // Counts: rows = ground truth, columns = prediction.
  long long at(int gt, int pred) const { return counts_[std::size_t(gt) * n_ + pred]; }
  int size() const { return n_; }

  // Metrics; classes in `exclude` are left out of the mIoU (their pixels still count in accuracy).
  SegMetrics metrics(const std::vector<ClassId>& exclude = {}) const;

  // Heat map (BGR), row-normalised (each GT row sums to 1), with class names and percentages; only
  // classes present in GT or prediction are drawn.
  cv::Mat render(const ClassList& classes) const;

 private:
  int n_;
  std::vector<long long> counts_;
};

// Human-readable table: class, IoU, GT pixels; then mIoU and pixel accuracy.
std::string format_metrics(const SegMetrics& m, const ClassList& classes);

}  // namespace s3m::semantics
