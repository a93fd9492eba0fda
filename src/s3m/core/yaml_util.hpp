#pragma once
// Small helpers to read Config structs from YAML with errors that name the file and key.
// Pattern for a module config:
//   struct FooConfig { double max_range_m = 4.0; void validate() const; };
//   FooConfig c; yaml_get(node, "max_range_m", c.max_range_m, ctx); c.validate();
// Keys absent from YAML keep their defaults; unknown keys are reported by check_known_keys().
#include <string>
#include <vector>

#include <yaml-cpp/yaml.h>

#include "s3m/core/error.hpp"

namespace s3m {

// Loads a YAML file; throws ParseError with the file name and yaml-cpp's line on syntax errors,
// or "file not found".
YAML::Node load_yaml_file(const std::string& path);

// Reads node[key] into out when present. ctx names the file/section for messages.
template <typename T>
void yaml_get(const YAML::Node& node, const std::string& key, T& out, const std::string& ctx) {
  const YAML::Node v = node[key];
  if (!v) return;
  try {
    out = v.as<T>();
  } catch (const YAML::Exception&) {
    throw ParseError(ctx, v.Mark().line + 1, "bad value for '" + key + "'", "a value of the right type");
  }
}

// Throws ParseError if node (a map) has a key not listed in known; catches typos in configs.
void check_known_keys(const YAML::Node& node, const std::vector<std::string>& known, const std::string& ctx);

}  // namespace s3m
