#include "s3m/mapping/mapping_config.hpp"

#include "s3m/core/config_table.hpp"
#include "s3m/core/error.hpp"
#include "s3m/core/yaml_util.hpp"

namespace s3m::mapping {

void MappingConfig::validate() const {
  require(resolution_m >= 0.005 && resolution_m <= 1.0, "mapping.resolution_m must be in [0.005, 1] m");
  occupancy.validate();
  fusion.validate();
  insert.validate();
}

void fields(config::FieldVisitor& v, OccupancyParams& c) {
  v("prob_hit", c.prob_hit);
  v("prob_miss", c.prob_miss);
  v("clamp_min", c.clamp_min);
  v("clamp_max", c.clamp_max);
  v("occupancy_thres", c.occupancy_thres);
}

void fields(config::FieldVisitor& v, MappingConfig& c) {
  v("resolution_m", c.resolution_m);
  v("keep_session_surfaces", c.keep_session_surfaces);
  v("occupancy", c.occupancy);
  v("fusion", c.fusion);
  v("insert", c.insert);
}

MappingConfig load_mapping_config(const YAML::Node& node, const std::string& ctx) {
  MappingConfig c;
  if (!node) return c;
  config::read(node, config::table_of(c), ctx);
  try {
    c.validate();
  } catch (const Error& e) {
    throw ParseError(ctx, node.Mark().line + 1, e.what(), "values in the documented ranges");
  }
  return c;
}

MappingConfig load_mapping_config_file(const std::string& path) {
  const YAML::Node root = load_yaml_file(path);
  return load_mapping_config(root["mapping"] ? root["mapping"] : root, path);
}

std::unique_ptr<SemanticOcTree> make_semantic_map(const MappingConfig& cfg, const ClassList& classes) {
  cfg.validate();
  auto tree = std::make_unique<SemanticOcTree>(cfg.resolution_m);
  tree->setOccupancyParams(cfg.occupancy);
  FusionConfig fusion = cfg.fusion;
  fusion.num_classes = int(classes.size());
  tree->setFusionConfig(fusion);
  tree->setClasses(classes);
  return tree;
}

}  // namespace s3m::mapping
