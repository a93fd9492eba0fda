#pragma once
// Everything that configures the semantic map, loadable from YAML (see config/mapping.yaml):
//   resolution_m: 0.05
//   keep_session_surfaces: true
//   occupancy: {prob_hit, prob_miss, clamp_min, clamp_max, occupancy_thres}
//   fusion:    {policy: paper|max_confidence|bayesian, k, alpha, min_other, max_decay, num_classes}
//   insert:    {min_range_m, max_range_m, clear_beyond_max_range, clear_free_space,
//               radius_min_neighbors, min_points_per_voxel, sor_neighbors, sor_std_mul, num_threads}
#include <memory>
#include <string>

#include <yaml-cpp/yaml.h>

#include "s3m/mapping/insert.hpp"
#include "s3m/mapping/semantic_octree.hpp"

namespace s3m::mapping {

struct MappingConfig {
  double resolution_m = 0.05;  // leaf voxel edge [m]
  // A map rebuilt from the clouds of several sessions (a run continuing a loaded map, `s3m merge`)
  // keeps every voxel that one session's clouds alone make occupied, even where another session's
  // rays held it free. Log-odds fusion alone lets one flight's free-space evidence erase a surface
  // the other saw (a shelf edge one flight passed just above); for a map flown in, a surface that a
  // session saw stays an obstacle. The price: something that moved between the sessions stays in
  // both places. Within one session occupancy is plain log-odds either way.
  bool keep_session_surfaces = true;
  OccupancyParams occupancy;
  FusionConfig fusion;
  InsertConfig insert;
  void validate() const;  // throws s3m::Error naming the field
};

// Its YAML keys with the members they fill (core/config_table.hpp), and those of its occupancy.
void fields(config::FieldVisitor& v, MappingConfig& c);
void fields(config::FieldVisitor& v, OccupancyParams& c);

// Reads a `mapping:`-style YAML map (keys above; absent keys keep defaults, unknown keys are
// errors). ctx names the file/section in messages.
MappingConfig load_mapping_config(const YAML::Node& node, const std::string& ctx);
MappingConfig load_mapping_config_file(const std::string& path);

// An empty map configured by cfg; fusion.num_classes is set to the class list's size.
std::unique_ptr<SemanticOcTree> make_semantic_map(const MappingConfig& cfg,
                                                  const ClassList& classes = indoor_classes());

}  // namespace s3m::mapping
