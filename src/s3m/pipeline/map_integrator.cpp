#include "s3m/pipeline/map_integrator.hpp"

#include <cmath>
#include <set>

#include "s3m/core/error.hpp"
#include "s3m/mapping/export.hpp"
#include "s3m/mapping/map_io.hpp"
#include "s3m/pipeline/cloud_from_frame.hpp"

namespace s3m::pipeline {

MapIntegrator::MapIntegrator(const MapConfig& config, std::vector<ClassId> dynamic)
    : config_(config), inserter_(config.insert, std::move(dynamic)) {
  config_.validate();
  tree_ = make_tree();
}

std::unique_ptr<mapping::SemanticOcTree> MapIntegrator::make_tree() const {
  return mapping::make_semantic_map(config_);
}

void MapIntegrator::insert(const mapping::LabeledCloud& cloud_c, const SE3& T_w_c) {
  inserter_.insert(transformed(cloud_c, T_w_c), *tree_);
}

void MapIntegrator::rebuild(const KeyframeStore& store) {
  auto fresh = map_of(store, kAllSessions);
  const std::set<int> sessions = store.sessions_in_world();
  session_voxels_kept_ = 0;
  if (config_.keep_session_surfaces && sessions.size() > 1)
    for (int s : sessions) session_voxels_kept_ += restore_occupied(*map_of(store, s), *fresh);
  tree_ = std::move(fresh);
}

// The map of the kept clouds in the world of one session (or all of them), in their order, at
// their current poses.
std::unique_ptr<mapping::SemanticOcTree> MapIntegrator::map_of(const KeyframeStore& store, int session) {
  auto tree = make_tree();
  for (const KeptCloud& c : store.clouds())
    if (store.in_world(c) && (session == kAllSessions || c.session == session))
      inserter_.insert(transformed(c.cloud, store.T_w_c(c)), *tree);
  return tree;
}

std::size_t MapIntegrator::occupied_voxels() const {
  std::size_t n = 0;
  const unsigned max_depth = tree_->getTreeDepth();
  for (auto it = tree_->begin_leafs(), end = tree_->end_leafs(); it != end; ++it)
    if (tree_->isNodeOccupied(*it))
      n += std::size_t{1} << (3 * (max_depth - it.getDepth()));  // pruned leaves
  return n;
}

void MapIntegrator::save(const std::string& ot_path, const std::string& ply_path) const {
  mapping::save_semantic_map(*tree_, ot_path);
  mapping::export_ply(*tree_, ply_path, mapping::PlyColor::kObserved);
}

nlohmann::json MapIntegrator::describe() const {
  return {{"voxels", occupied_voxels()},
          {"leaf_nodes", tree_->getNumLeafNodes()},
          {"resolution_m", config_.resolution_m},
          {"session_voxels_kept", session_voxels_kept_},
          {"fusion_policy", mapping::to_string(config_.fusion.policy)},
          {"top_k", config_.fusion.k},
          {"alpha", config_.fusion.alpha}};
}

}  // namespace s3m::pipeline
