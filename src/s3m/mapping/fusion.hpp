#pragma once
// Label fusion policies: how a voxel's stored top-k labels (Q1) absorb a new observation (Q2).
// Interchangeable strategies selected by FusionConfig::policy (see docs/MAPPING.md for the
// hand-worked examples and the edge cases the paper leaves open).
#include <string>

#include <yaml-cpp/yaml.h>

#include "s3m/mapping/label_set.hpp"

namespace s3m::config {
class FieldVisitor;
}

namespace s3m::mapping {

enum class FusionPolicy : std::uint8_t {
  kPaper = 0,          // the paper's Algorithm 1 (alpha trade-off, product + normalise)
  kMaxConfidence = 1,  // keep the most confident list; average on agreement, decay on disagreement
  kBayesian = 2,       // multiply-and-normalise over top-k + a uniform "other" bin
};

struct FusionConfig {
  FusionPolicy policy = FusionPolicy::kPaper;
  int k = 3;  // labels kept per voxel, 1..kMaxLabels
  // Algorithm 1's trade-off: a label missing from one list gets alpha * p-bar of that list.
  // 0.5 halves the unexplained mass per pushed label, so pushed labels keep their rank order
  // and never exhaust p-bar (the geometric series alpha*(1-alpha)^i sums to < 1).
  double alpha = 0.5;
  // Floor for the unexplained mass p-bar (paper: 1 - sum p, which is 0 for a full softmax
  // top-k list and would zero every label the other view did not list).
  double min_other = 1e-3;
  double max_decay = 0.9;         // max-confidence: factor applied to the kept list on disagreement
  int num_classes = cls::kCount;  // Bayesian: "other" mass is spread over the classes not listed

  void validate() const;  // throws s3m::Error naming the bad field
};

// Reads the keys of FusionConfig from a YAML map (policy: paper | max_confidence | bayesian).
FusionConfig fusion_config_from_yaml(const YAML::Node& node, const std::string& ctx);
// Its YAML keys with the members they fill (core/config_table.hpp).
void fields(config::FieldVisitor& v, FusionConfig& c);
std::string to_string(FusionPolicy policy);
FusionPolicy parse_fusion_policy(const std::string& name);  // throws s3m::Error

// A strategy: fuses obs into map in place. map must be normalised; obs need not be.
using FusionFn = void (*)(LabelSet& map, const LabelSet& obs, const FusionConfig& cfg);
FusionFn fusion_function(FusionPolicy policy);

void fuse_paper(LabelSet& map, const LabelSet& obs, const FusionConfig& cfg);
void fuse_max_confidence(LabelSet& map, const LabelSet& obs, const FusionConfig& cfg);
void fuse_bayesian(LabelSet& map, const LabelSet& obs, const FusionConfig& cfg);

}  // namespace s3m::mapping
