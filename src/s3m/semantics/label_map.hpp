#pragma once
// Per-pixel top-k semantic labels, the currency between segmenters, the map and the evaluation.
// Stored as a few cv::Mat planes (not per-pixel structs) so producing and consuming them is cheap.
#include <vector>

#include <opencv2/core.hpp>

#include "s3m/core/classes.hpp"

namespace s3m::semantics {

// Top-k labels per pixel, most probable first. All three images have the camera image's size.
//   ids    CV_16UC(k)  project class ids (s3m::ClassId); channel j holds the (j+1)-th most probable
//   probs  CV_32FC(k)  their probabilities in [0,1], non-increasing along the channels, sum <= 1
//                      (the mass of the classes beyond the top k is not stored: p̄ = 1 - Σp)
//   argmax CV_16UC1    a copy of channel 0 of ids (what most consumers need)
// A pixel with no prediction (e.g. unlabelled ground truth for the oracle) has id 0 (unknown), prob 0.
struct LabelMap {
  cv::Mat ids;
  cv::Mat probs;
  cv::Mat argmax;

  bool empty() const { return ids.empty(); }
  int k() const { return ids.empty() ? 0 : ids.channels(); }
  int rows() const { return ids.rows; }
  int cols() const { return ids.cols; }
  // j-th label / probability of pixel (row, col); j < k(). No bounds checks: inner-loop accessors.
  ClassId id(int row, int col, int j) const { return ids.ptr<ClassId>(row)[col * k() + j]; }
  float prob(int row, int col, int j) const { return probs.ptr<float>(row)[col * k() + j]; }
};

// An empty LabelMap with all ids 0 (unknown) and probabilities 0.
LabelMap make_label_map(int rows, int cols, int k);

// In-place softmax across planes (one CV_32FC1 plane per class, all the same size): numerically
// stable (max subtracted first), so every pixel's values sum to 1 over the planes.
void softmax_planes(std::vector<cv::Mat>& planes);

// Per-pixel top-k of class score planes. planes[i] (CV_32FC1) scores class plane_ids[i]. Ties keep
// the lower plane index first so results are deterministic. If k > planes.size() the tail is 0/0.
LabelMap topk_from_planes(const std::vector<cv::Mat>& planes, const std::vector<ClassId>& plane_ids, int k);

// Colour image (CV_8UC3, BGR) of a class-id image (CV_16UC1) with the list's palette; ids outside
// the list are drawn magenta so they stand out.
cv::Mat colorize(const cv::Mat& ids16, const ClassList& classes);

// Blend of the image and the colourised labels (alpha = weight of the labels), BGR.
cv::Mat overlay(const cv::Mat& bgr, const cv::Mat& ids16, const ClassList& classes, double alpha = 0.5);

}  // namespace s3m::semantics
