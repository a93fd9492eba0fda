#pragma once
// Small helpers to read Config structs from YAML with errors that name the file and key.
// Config structs list their keys in a table (config_table.hpp), whose reader uses these.
#include <string>
#include <vector>

#include <yaml-cpp/yaml.h>

#include "s3m/core/error.hpp"

namespace s3m {

// Loads a YAML file; throws ParseError with the file name and yaml-cpp's line on syntax errors,
// or "file not found".
YAML::Node load_yaml_file(const std::string& path);

// The value v of key as a T; ctx names the file/section for messages.
template <typename T>
T yaml_as(const YAML::Node& v, const std::string& key, const std::string& ctx) {
  try {
    return v.as<T>();
  } catch (const YAML::Exception&) {
    throw ParseError(ctx, v.Mark().line + 1, "bad value for '" + key + "'", "a value of the right type");
  }
}

// Reads node[key] into out when present.
template <typename T>
void yaml_get(const YAML::Node& node, const std::string& key, T& out, const std::string& ctx) {
  if (const YAML::Node v = node[key]) out = yaml_as<T>(v, key, ctx);
}

// Throws ParseError if node (a map) has a key not listed in known; catches typos in configs.
void check_known_keys(const YAML::Node& node, const std::vector<std::string>& known, const std::string& ctx);

}  // namespace s3m
