#pragma once
// OracleSegmenter: a Segmenter for simulated data that reads the ground-truth label image
// (RgbdFrame::labels) and, optionally, corrupts it the way a real network errs, with a seed, so the
// fusion can be tested against known truth.
//
// Noise model (all per frame, deterministic given seed and frame index):
//  - Regions = connected components (8-connected) of each ground-truth class.
//  - Each region draws a confidence c ~ Beta(mean 1 - (confusion_rate + drop_rate), concentration),
//    clamped to [min_confidence, 1]; the region is wrong with probability 1 - c. A wrong region is
//    "dropped" (takes the label of the class surrounding it) with probability drop_rate / (sum of the
//    two rates), otherwise "confused" (relabelled to a similar class from `similar`).
//  - Pixels within boundary_width_px (Chebyshev) of another labelled class take that class with
//    probability boundary_flip_prob.
//  - Calibrated confidences: the top-1 probability of a pixel is c for region interiors and
//    c * (1 - boundary_flip_prob) in boundary bands, so P(top-1 correct | its probability = p) = p.
//  - The remaining mass 1 - p1 goes to ranks 2..k in shares 0.6, 0.24, 0.096, ... of it (each capped at
//    the rank above, so ranks stay ordered), rank 2 being
//    the true class when top-1 is wrong (else the true class's most similar class).
// Ground-truth "unknown" (0) pixels get id 0 with probability 0 at every rank.
#include <cstdint>
#include <map>
#include <string>
#include <vector>

#include <yaml-cpp/yaml.h>

#include "s3m/semantics/segmenter.hpp"

namespace s3m::config {
class FieldVisitor;
}

namespace s3m::semantics {

struct OracleNoiseConfig {
  bool enabled = false;             // false: labels copied exactly with probability 1
  double confusion_rate = 0.10;     // expected fraction of regions relabelled to a similar class
  double drop_rate = 0.05;          // expected fraction of regions replaced by their surroundings' class
  int boundary_width_px = 2;        // half-width of the band around class boundaries [px]
  double boundary_flip_prob = 0.3;  // probability a band pixel takes the neighbouring class
  double concentration = 20.0;      // Beta concentration of region confidences (higher = less spread)
  double min_confidence = 0.4;      // confidences are clamped up to this (keeps rank 1 >= rank 2)
  std::uint64_t seed = 0;
  // Project class name -> similar classes a network confuses it with (defaults: default_similar()).
  std::map<ClassId, std::vector<ClassId>> similar;
  void validate() const;
};

// Indoor confusions a segmentation network typically makes (wall<->door/window, chair<->sofa, ...).
std::map<ClassId, std::vector<ClassId>> default_similar();

// Reads an `oracle:` YAML section (keys as in OracleNoiseConfig; similar: {wall: [door, window]}).
OracleNoiseConfig load_oracle_config(const YAML::Node& node, const std::string& ctx);
// Its YAML keys with the members they fill (core/config_table.hpp).
void fields(config::FieldVisitor& v, OracleNoiseConfig& c);

class OracleSegmenter : public Segmenter {
 public:
  explicit OracleSegmenter(OracleNoiseConfig config = {}, int k = 3);

  // Needs ground truth: throws s3m::Error (use segment(frame)).
  LabelMap segment(const cv::Mat& bgr) override;
  // frame.labels (CV_16UC1 project ids) -> noisy top-k; frame.index seeds the noise.
  LabelMap segment(const RgbdFrame& frame) override;
  LabelMap segment_labels(const cv::Mat& gt_labels, int frame_index = 0) const;
  int top_k() const override { return k_; }
  std::string name() const override { return config_.enabled ? "oracle+noise" : "oracle"; }

 private:
  OracleNoiseConfig config_;
  int k_;
};

}  // namespace s3m::semantics
