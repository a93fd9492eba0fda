#pragma once
// DistanceField: a Euclidean distance field over a semantic OctoMap, computed and kept up to date
// by Debian's dynamicEDT3D (DynamicEDTOctomapBase, the OctoMap authors' incremental EDT). It covers
// the box of the map's known voxels; clearance() answers "how far is the nearest obstacle" for a
// world point. Units are metres, points are in the world frame of the map.
#include <memory>
#include <string>

#include <Eigen/Core>

#include "s3m/mapping/semantic_octree.hpp"

namespace s3m::navigation {

// What the field takes unobserved (unknown) voxels for.
enum class UnknownSpace {
  kOccupied,  // a flying robot must not enter space nobody has seen (default)
  kFree,      // optimistic: only observed obstacles count
};
UnknownSpace unknown_space_from_string(const std::string& name);  // "occupied" | "free"; throws otherwise
std::string to_string(UnknownSpace u);

struct DistanceFieldConfig {
  double max_distance_m = 2.0;  // distances saturate here; larger costs time per update
  UnknownSpace unknown = UnknownSpace::kOccupied;
  void validate() const;  // max_distance_m > 0
};

class DistanceField {
 public:
  // Computes the field over `tree`'s known extent. The tree must outlive the field; the field turns
  // on the tree's change detection so that update() can follow later map changes incrementally.
  DistanceField(mapping::SemanticOcTree& tree, const DistanceFieldConfig& cfg = {});
  ~DistanceField();
  DistanceField(const DistanceField&) = delete;
  DistanceField& operator=(const DistanceField&) = delete;

  // Folds in every voxel whose occupancy changed since the last update (OctoMap's change detection:
  // updateNode / insertPointCloud record them) inside the field's box. SemanticOcTree::
  // applyFrameUpdate, the pipeline's parallel insertion, records no changes yet: after it, build a
  // new field.
  void update();

  // Distance [m] from p_w to the centre of the nearest obstacle voxel, measured between voxel
  // centres (so within half a voxel diagonal of the exact point distance), saturated at
  // max_distance_m. 0 inside an obstacle; outside the box 0 when unknown space is occupied, else
  // max_distance_m.
  double clearance(const Eigen::Vector3d& p_w) const;
  bool contains(const Eigen::Vector3d& p_w) const;

  // The field's box [m]: centres of its lowest and highest voxels. It spans the map's known voxels,
  // plus one voxel all round when unknown space counts as occupied.
  const Eigen::Vector3d& min_w() const { return min_w_; }
  const Eigen::Vector3d& max_w() const { return max_w_; }
  double resolution() const { return resolution_; }
  const DistanceFieldConfig& config() const { return cfg_; }
  const mapping::SemanticOcTree& tree() const { return tree_; }

 private:
  struct Edt;
  mapping::SemanticOcTree& tree_;
  DistanceFieldConfig cfg_;
  double resolution_ = 0.0;
  Eigen::Vector3d min_w_, max_w_;
  std::unique_ptr<Edt> edt_;
};

}  // namespace s3m::navigation
