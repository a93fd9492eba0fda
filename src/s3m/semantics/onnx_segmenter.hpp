#pragma once
// OnnxSegmenter: any NCHW semantic-segmentation ONNX model through OpenCV DNN (CPU), described by a
// YAML model card (model_card.hpp). Model classes are mapped many-to-one onto the project classes by
// SUMMING their probabilities (after the softmax over the model's own classes), then the top k
// project classes are kept — so "table" collects desk + coffee table + table before ranking.
#include <memory>
#include <string>
#include <vector>

#include <opencv2/dnn.hpp>

#include "s3m/semantics/class_map.hpp"
#include "s3m/semantics/model_card.hpp"
#include "s3m/semantics/onnx_inspect.hpp"
#include "s3m/semantics/segmenter.hpp"

namespace s3m::semantics {

class OnnxSegmenter : public Segmenter {
 public:
  // Loads the model and checks it against the card; throws s3m::Error / ParseError with the file
  // and the problem (missing/corrupt model, input size differing from the model's declared input,
  // class list length != output channels, bad class map).
  explicit OnnxSegmenter(ModelCard card);
  static std::unique_ptr<OnnxSegmenter> from_card(const std::string& card_path,
                                                  const std::string& model_dir = "");

  LabelMap segment(const cv::Mat& bgr) override;
  using Segmenter::segment;
  int top_k() const override { return card_.top_k; }
  std::string name() const override { return card_.name; }

  const ModelCard& card() const { return card_; }
  const ClassMap& class_map() const { return map_; }
  const std::vector<std::string>& model_classes() const { return model_classes_; }
  // Output grid size of the network [px] (equals the input size unless the model is strided).
  cv::Size output_size() const { return output_size_; }

 private:
  // Where the network input sits in the camera image: camera pixel u -> network input pixel
  // x = (u + 0.5) * scale_x - 0.5 + offset_x (same for y).
  struct Geometry {
    double scale_x = 1, scale_y = 1, offset_x = 0, offset_y = 0;
  };
  cv::Mat preprocess(const cv::Mat& bgr, Geometry& geo) const;
  cv::Mat forward(const cv::Mat& blob);
  void require_finite(const cv::Mat& out) const;
  std::vector<cv::Mat> project_probabilities(const cv::Mat& out) const;
  cv::Mat camera_to_output(const Geometry& geo) const;  // 2x3 affine, camera px -> output px
  void check_model(const OnnxInputInfo& in);

  ModelCard card_;
  cv::dnn::Net net_;
  std::vector<std::string> model_classes_;
  ClassMap map_;
  std::vector<bool> ignored_;    // per model class: excluded from the softmax
  std::vector<ClassId> active_;  // project classes that receive probability mass
  cv::Size output_size_;
};

}  // namespace s3m::semantics
