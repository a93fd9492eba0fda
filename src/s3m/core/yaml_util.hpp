#pragma once
// Small helpers to read YAML files with errors that name the file, the line and the key. Config
// structs list their keys in a table (config_table.hpp), whose reader uses these; the other file
// formats (camera, model card, class map) read their maps with YamlMap.
#include <functional>
#include <string>
#include <utility>
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

// A YAML map whose keys are each named once, in the read that takes them. The reads are declared
// first; read() then refuses a key that no read takes (a ParseError with the file, the line, the
// key and the keys the map takes) before it runs any, so that a misspelt key is reported as such
// rather than as the key it should have been missing, and runs them in the order declared:
//   YamlMap m(node, path);
//   m.get("fx", cam.fx).on("T_c_d", [&](const YAML::Node& v, const std::string& key) { ... });
//   m.read();
// A node that is a value or a list where the map belongs is refused the same way; an empty one
// (null) reads as a map without keys.
class YamlMap {
 public:
  // value: the key's node, undefined (!value) when the map lacks the key (always() only).
  using Read = std::function<void(const YAML::Node& value, const std::string& key)>;

  YamlMap(YAML::Node node, std::string ctx) : node_(std::move(node)), ctx_(std::move(ctx)) {}

  // out = the key's value as a T, when present.
  template <typename T>
  YamlMap& get(const std::string& key, T& out) {
    return on(key,
              [&out, ctx = ctx_](const YAML::Node& v, const std::string& k) { out = yaml_as<T>(v, k, ctx); });
  }
  // read(value, key) when the key is present.
  YamlMap& on(const std::string& key, Read read);
  // read(value, key) also when it is absent: a required key, a default that depends on it.
  YamlMap& always(const std::string& key, Read read);
  // A key taken and not read (a note for people).
  YamlMap& ignore(const std::string& key);

  void read() const;

 private:
  struct Entry {
    std::string key;
    Read read;  // empty: ignored
    bool always = false;
  };
  const YAML::Node node_;
  std::string ctx_;
  std::vector<Entry> entries_;
};

}  // namespace s3m
