#pragma once
// The Segmenter interface: one colour image in, per-pixel top-k project labels out.
#include <memory>
#include <string>

#include <opencv2/core.hpp>

#include "s3m/core/rgbd_frame.hpp"
#include "s3m/semantics/label_map.hpp"

namespace s3m::semantics {

class Segmenter {
 public:
  virtual ~Segmenter() = default;
  // bgr: CV_8UC3 camera image (OpenCV BGR order). Returns a LabelMap of the same size.
  // Not const: implementations may keep scratch buffers or state; not thread-safe per instance.
  virtual LabelMap segment(const cv::Mat& bgr) = 0;
  // The pipeline calls this one: frame-aware segmenters (the oracle reads frame.labels and seeds its
  // noise with frame.index) override it; image segmenters just use frame.rgb.
  virtual LabelMap segment(const RgbdFrame& frame) { return segment(frame.rgb); }
  virtual int top_k() const = 0;
  virtual std::string name() const = 0;
};

}  // namespace s3m::semantics
