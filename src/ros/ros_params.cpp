#include "ros_params.hpp"

#include <cstdio>

#include <xmlrpcpp/XmlRpcValue.h>

#include "s3m/core/error.hpp"
#include "s3m/core/yaml_util.hpp"

namespace s3m::ros1 {
namespace {

const char* const kSections[] = {"dataset", "slam", "cloud", "threads", "flow", "eval", "map", "segmenter"};

std::string scalar(double v) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.17g", v);
  return buf;
}

YAML::Node to_yaml(XmlRpc::XmlRpcValue& v) {
  switch (v.getType()) {
    case XmlRpc::XmlRpcValue::TypeBoolean: return YAML::Node(static_cast<bool>(v) ? "true" : "false");
    case XmlRpc::XmlRpcValue::TypeInt: return YAML::Node(std::to_string(static_cast<int>(v)));
    case XmlRpc::XmlRpcValue::TypeDouble: return YAML::Node(scalar(static_cast<double>(v)));
    case XmlRpc::XmlRpcValue::TypeString: return YAML::Node(static_cast<std::string>(v));
    case XmlRpc::XmlRpcValue::TypeArray: {
      YAML::Node seq(YAML::NodeType::Sequence);
      for (int i = 0; i < v.size(); ++i) seq.push_back(to_yaml(v[i]));
      return seq;
    }
    case XmlRpc::XmlRpcValue::TypeStruct: {
      YAML::Node map(YAML::NodeType::Map);
      for (auto& [key, value] : v) map[key] = to_yaml(value);
      return map;
    }
    default: throw Error("ROS parameter of an unsupported type (expected bool, number, string, list or dict)");
  }
}

}  // namespace

YAML::Node merge_yaml(YAML::Node base, const YAML::Node& overrides) {
  if (!overrides.IsMap() || !base.IsMap()) return YAML::Clone(overrides);
  YAML::Node out = YAML::Clone(base);
  for (const auto& kv : overrides) {
    const std::string key = kv.first.as<std::string>();
    out[key] = out[key] ? merge_yaml(out[key], kv.second) : YAML::Clone(kv.second);
  }
  return out;
}

pipeline::PipelineConfig config_from_params(const ros::NodeHandle& pnh) {
  std::string preset;
  pnh.param<std::string>("config", preset, "");
  YAML::Node root = preset.empty() ? YAML::Node(YAML::NodeType::Map) : load_yaml_file(preset);
  if (!root || root.IsNull()) root = YAML::Node(YAML::NodeType::Map);
  YAML::Node overrides(YAML::NodeType::Map);
  for (const char* section : kSections) {
    XmlRpc::XmlRpcValue v;
    if (!pnh.getParam(section, v)) continue;
    // ~map as a string is the saved run to continue in (node.hpp), not the map section.
    if (std::string(section) == "map" && v.getType() == XmlRpc::XmlRpcValue::TypeString) continue;
    try {
      overrides[section] = to_yaml(v);
    } catch (const Error& e) {
      throw Error(pnh.resolveName(section) + ": " + e.what());
    }
  }
  root = merge_yaml(root, overrides);
  // No slash in the default name: relative paths in the parameters stay relative to the working dir.
  const std::string source = preset.empty() ? "(ROS parameters)" : preset;
  return pipeline::pipeline_config_from_yaml(root, source);
}

}  // namespace s3m::ros1
