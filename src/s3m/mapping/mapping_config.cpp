#include "s3m/mapping/mapping_config.hpp"

#include "s3m/core/error.hpp"
#include "s3m/core/yaml_util.hpp"

namespace s3m::mapping {

void MappingConfig::validate() const {
  require(resolution_m >= 0.005 && resolution_m <= 1.0, "mapping.resolution_m must be in [0.005, 1] m");
  occupancy.validate();
  fusion.validate();
  insert.validate();
}

MappingConfig load_mapping_config(const YAML::Node& node, const std::string& ctx) {
  MappingConfig c;
  if (!node) return c;
  check_known_keys(node, {"resolution_m", "keep_session_surfaces", "occupancy", "fusion", "insert"}, ctx);
  yaml_get(node, "resolution_m", c.resolution_m, ctx);
  yaml_get(node, "keep_session_surfaces", c.keep_session_surfaces, ctx);
  if (const YAML::Node o = node["occupancy"]) {
    check_known_keys(o, {"prob_hit", "prob_miss", "clamp_min", "clamp_max", "occupancy_thres"}, ctx);
    yaml_get(o, "prob_hit", c.occupancy.prob_hit, ctx);
    yaml_get(o, "prob_miss", c.occupancy.prob_miss, ctx);
    yaml_get(o, "clamp_min", c.occupancy.clamp_min, ctx);
    yaml_get(o, "clamp_max", c.occupancy.clamp_max, ctx);
    yaml_get(o, "occupancy_thres", c.occupancy.occupancy_thres, ctx);
  }
  c.fusion = fusion_config_from_yaml(node["fusion"], ctx);
  c.insert = insert_config_from_yaml(node["insert"], ctx);
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
