#pragma once
// The pipeline's handle on the semantic map (s3m::mapping): inserts camera-frame labelled clouds at
// a pose, rebuilds the map from the kept clouds when keyframe poses change, saves and scores it.
#include <memory>
#include <string>

#include <yaml-cpp/yaml.h>
#include <nlohmann/json.hpp>

#include "s3m/core/se3.hpp"
#include "s3m/mapping/insert.hpp"
#include "s3m/mapping/semantic_octree.hpp"
#include "s3m/pipeline/keyframe_store.hpp"
#include "s3m/pipeline/pipeline_config.hpp"

namespace s3m::pipeline {

class MapIntegrator {
 public:
  // dynamic: classes whose voxels are not made occupied (mapping::Inserter).
  explicit MapIntegrator(const MapConfig& config, std::vector<ClassId> dynamic = {});

  // Inserts cloud_c (camera frame, origin 0) observed from T_w_c; rays from the camera centre clear
  // free space.
  void insert(const mapping::LabeledCloud& cloud_c, const SE3& T_w_c);
  // Replaces the map by one built from every kept cloud in the world at its current pose, in the
  // original order. With clouds of several sessions and map.keep_session_surfaces, every voxel a
  // session's own clouds make occupied stays occupied (mapping::restore_occupied).
  void rebuild(const KeyframeStore& store);
  // map.ot (full semantics, atomic) and map.ply (occupied leaves: centre, colour, class, confidence).
  void save(const std::string& ot_path, const std::string& ply_path) const;

  const mapping::SemanticOcTree& tree() const { return *tree_; }
  double resolution_m() const { return config_.resolution_m; }
  std::size_t occupied_voxels() const;
  // Statistics for metrics.json: voxels, resolution, fusion parameters.
  nlohmann::json describe() const;

 private:
  std::unique_ptr<mapping::SemanticOcTree> make_tree() const;
  static constexpr int kAllSessions = -1;
  std::unique_ptr<mapping::SemanticOcTree> map_of(const KeyframeStore& store, int session);

  MapConfig config_;
  mapping::Inserter inserter_;
  std::unique_ptr<mapping::SemanticOcTree> tree_;
  std::size_t session_voxels_kept_ = 0;  // voxels the last rebuild kept for one session's surfaces
};

}  // namespace s3m::pipeline
