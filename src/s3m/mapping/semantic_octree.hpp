#pragma once
// SemanticOcTree: an OctoMap occupancy octree whose voxels also carry colour and top-k class
// labels with probabilities. Follows OctoMap's ColorOcTree pattern: a node type deriving from
// OcTreeNode, a tree deriving from OccupancyOcTreeBase<node>, node readData/writeData for .ot
// persistence, and the tree type "SemanticOcTree" registered with AbstractOcTree's factory.
// Coordinates are world-frame metres; occupancy is log-odds as in OctoMap.
#include <cstdint>
#include <istream>
#include <ostream>
#include <string>

#include <octomap/OccupancyOcTreeBase.h>
#include <octomap/OcTreeNode.h>

#include "s3m/core/classes.hpp"
#include "s3m/mapping/fusion.hpp"
#include "s3m/mapping/label_set.hpp"

namespace s3m::mapping {

class SemanticOcTree;
struct FrameUpdate;
struct TreeUpdater;

struct Rgb {
  std::uint8_t r = 0, g = 0, b = 0;
  bool operator==(const Rgb& o) const { return r == o.r && g == o.g && b == o.b; }
};

class SemanticOcTreeNode : public octomap::OcTreeNode {
 public:
  friend class SemanticOcTree;  // tree code manipulates children directly (as ColorOcTree does)
  friend struct TreeUpdater;

  SemanticOcTreeNode() = default;
  SemanticOcTreeNode(const SemanticOcTreeNode& rhs)
      : OcTreeNode(rhs), labels_(rhs.labels_), color_(rhs.color_), color_count_(rhs.color_count_) {}
  SemanticOcTreeNode& operator=(const SemanticOcTreeNode&) = delete;

  // Equality of all payload (used by OctoMap's pruning: only identical children collapse).
  bool operator==(const SemanticOcTreeNode& rhs) const {
    return rhs.value == value && rhs.labels_ == labels_ && rhs.color_ == color_ &&
           rhs.color_count_ == color_count_;
  }
  void copyData(const SemanticOcTreeNode& from) {
    OcTreeNode::copyData(from);
    labels_ = from.labels_;
    color_ = from.color_;
    color_count_ = from.color_count_;
  }

  const LabelSet& labels() const { return labels_; }
  LabelSet& labels() { return labels_; }
  bool hasColor() const { return color_count_ > 0; }
  Rgb color() const { return color_; }
  void setColor(Rgb c) { color_ = c, color_count_ = 1; }
  // Running mean over the first kColorWindow observations, exponential after that, so the
  // colour settles but can still follow lighting changes.
  void integrateColor(Rgb c);

  // Inner-node aggregation, called by OctoMap's update code on every touched inner node:
  // occupancy = max child (conservative, as OcTreeNode), labels = those of the most confident
  // occupied child (any child if none is occupied), colour = that child's colour.
  void updateOccupancyChildren();

  std::istream& readData(std::istream& s);
  std::ostream& writeData(std::ostream& s) const;

  static constexpr std::uint8_t kColorWindow = 8;

 private:
  LabelSet labels_;
  Rgb color_;
  std::uint8_t color_count_ = 0;  // 0 = no colour observed yet
};

struct OccupancyParams {
  double prob_hit = 0.7, prob_miss = 0.4;  // OctoMap defaults
  double clamp_min = 0.1192, clamp_max = 0.971;
  double occupancy_thres = 0.5;
  void validate() const;
};

class SemanticOcTree : public octomap::OccupancyOcTreeBase<SemanticOcTreeNode> {
 public:
  explicit SemanticOcTree(double resolution_m);
  SemanticOcTree* create() const override { return new SemanticOcTree(resolution); }
  std::string getTreeType() const override { return "SemanticOcTree"; }

  // Semantic parameters are part of the map (saved in .ot, restored by load).
  const FusionConfig& fusionConfig() const { return fusion_; }
  void setFusionConfig(const FusionConfig& cfg);  // validates
  const ClassList& classes() const { return classes_; }
  void setClasses(const ClassList& classes) { classes_ = classes; }
  OccupancyParams occupancyParams() const;
  void setOccupancyParams(const OccupancyParams& p);  // validates

  // Fuses one labelled, coloured observation into the leaf at key (creating it; no occupancy
  // change). Slow path for tests and tools; insertion uses applyFrameUpdate().
  SemanticOcTreeNode* integrateObservation(const octomap::OcTreeKey& key, const LabelSet& obs, Rgb color);

  // Applies one frame's free/occupied voxel sets in a single Morton-ordered pass over the tree,
  // subtrees in parallel (TBB); identical result for any thread count. See frame_update.hpp.
  void applyFrameUpdate(const FrameUpdate& update);

  // Recomputes all inner nodes from the leaves (after setNodeValue/updateNode with lazy_eval).
  void updateInnerOccupancy();

  // .ot data section: semantic header (k, fusion, occupancy params, class list), node stream
  // with its byte length and checksum. Throws s3m::Error on truncated or corrupt input.
  std::istream& readData(std::istream& s) override;
  std::ostream& writeData(std::ostream& s) const override;

 private:
  friend struct TreeUpdater;
  void updateInnerRecurs(SemanticOcTreeNode* node, unsigned depth);

  FusionConfig fusion_;
  FusionFn fuse_ = &fuse_paper;
  ClassList classes_ = indoor_classes();

  // Registers the tree type with AbstractOcTree's factory once per process (ColorOcTree pattern).
  class StaticMemberInitializer {
   public:
    StaticMemberInitializer();
    void ensureLinking() {}
  };
  static StaticMemberInitializer semantic_octree_member_init_;
};

// Copies into `into` every finest voxel that `from` holds occupied and `into` does not (unknown or
// free there): log-odds, labels and colour, as `from` has them. Both trees must have the same
// resolution; `from`'s pruned nodes are expanded. Returns the number of voxels copied. This is how
// a map built from several sessions keeps every session's surfaces (MappingConfig::
// keep_session_surfaces): `from` is one session's own map, `into` the map fused from all of them.
std::size_t restore_occupied(SemanticOcTree& from, SemanticOcTree& into);

}  // namespace s3m::mapping
