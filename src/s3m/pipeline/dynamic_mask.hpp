#pragma once
// Where the things that move (people) are in a frame before it is segmented: segmentation runs
// after tracking, on the frames that go into the map, so tracking gets the last segmented frame's
// pixels of dynamic classes, moved into the new frame through their depth and the camera motion
// since (the constant-velocity prediction), grown by a margin for the people's own motion.
#include <memory>
#include <mutex>
#include <vector>

#include <opencv2/core.hpp>

#include "s3m/core/camera.hpp"
#include "s3m/core/classes.hpp"
#include "s3m/core/se3.hpp"
#include "s3m/semantics/label_map.hpp"

namespace s3m::pipeline {

class DynamicMasker {
 public:
  DynamicMasker(const PinholeCamera& camera, std::vector<ClassId> classes, int margin_px);

  // A segmented frame (argmax class per pixel, CV_16UC1) with its depth and pose: its dynamic
  // pixels are what the next frames are masked with. Thread-safe.
  void set_reference(const cv::Mat& argmax, const cv::Mat& depth_m, const SE3& T_w_c);
  // The mask (CV_8UC1, 255 = dynamic) for a frame seen from T_w_c; empty without a reference or
  // when the reference has no dynamic pixel. Thread-safe.
  cv::Mat mask(const SE3& T_w_c) const;

 private:
  static constexpr int kStride = 2;  // reference pixels sampled every kStride in u and v
  struct Reference {
    SE3 T_w_c;
    std::vector<Eigen::Vector3f> p_c;  // dynamic pixels with depth, in the reference camera
    std::vector<cv::Point> no_depth;   // dynamic pixels without depth: kept where they were
  };
  PinholeCamera camera_;
  std::vector<ClassId> classes_;
  int margin_px_;
  mutable std::mutex mutex_;
  std::shared_ptr<const Reference> reference_;
};

// The pixels of a class image (CV_16UC1) whose class is one of classes, grown by margin_px
// (CV_8UC1, 255 = dynamic).
cv::Mat label_mask(const cv::Mat& class_ids, const std::vector<ClassId>& classes, int margin_px);

// The labels the map gets: pixels within margin_px of a pixel whose top class is dynamic become
// that class (probability 1), so the map makes no obstacle of them either. Segmenters blur class
// borders and depth mixes a person's edge with the background: those pixels would otherwise leave
// a person's outline in the map. Pixels of also_dynamic (CV_8UC1 or empty: the frame's tracking
// mask, what the frames before saw move) become classes.front() too: a frame whose segmentation
// misses a person does not map it. Returns labels unchanged (shared) when no pixel is dynamic.
semantics::LabelMap grow_dynamic_labels(const semantics::LabelMap& labels,
                                        const std::vector<ClassId>& classes, int margin_px,
                                        const cv::Mat& also_dynamic = cv::Mat());

// The pose a frame is predicted at from the last two tracked ones (constant velocity).
SE3 predict_pose(const SE3& T_w_prev, const SE3& T_w_last);

}  // namespace s3m::pipeline
