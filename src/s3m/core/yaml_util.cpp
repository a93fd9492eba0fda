#include "s3m/core/yaml_util.hpp"

#include <algorithm>

#include "s3m/core/input_file.hpp"

namespace s3m {

YAML::Node load_yaml_file(const std::string& path) {
  require_input_file(path, "a YAML file");
  try {
    return YAML::LoadFile(path);
  } catch (const YAML::Exception& e) {
    throw ParseError(path, e.mark.line + 1, "YAML syntax error: " + e.msg, "valid YAML");
  }
}

namespace {

// Throws ParseError if node (a map) has a key not listed in known; catches typos in configs.
void check_known_keys(const YAML::Node& node, const std::vector<std::string>& known, const std::string& ctx) {
  std::string list;
  for (const auto& k : known) list += (list.empty() ? "" : ", ") + k;
  // A section given as a value ('insert: nan', 'fusion: [1]'): without this, the reads that follow
  // would index a scalar and yaml-cpp would throw its own exception (found by fuzzing).
  if (node.IsScalar() || node.IsSequence())
    throw ParseError(ctx, node.Mark().line + 1,
                     node.IsScalar() ? "a value ('" + node.Scalar() + "') where a section is expected"
                                     : "a list where a section is expected",
                     "a map of keys 'name: value' (one of: " + list + ")");
  if (!node.IsMap()) return;
  for (const auto& kv : node) {
    // YAML allows sequences and maps as keys ('? [a, b]: 1'); no s3m config uses them.
    if (!kv.first.IsScalar())
      throw ParseError(ctx, kv.first.Mark().line + 1, "a key that is not a plain name",
                       "keys like 'name: value'");
    const auto key = kv.first.Scalar();
    if (std::find(known.begin(), known.end(), key) == known.end()) {
      throw ParseError(ctx, kv.first.Mark().line + 1, "unknown key '" + key + "'", "one of: " + list);
    }
  }
}

}  // namespace

YamlMap& YamlMap::on(const std::string& key, Read read) {
  entries_.push_back({key, std::move(read), false});
  return *this;
}

YamlMap& YamlMap::always(const std::string& key, Read read) {
  entries_.push_back({key, std::move(read), true});
  return *this;
}

YamlMap& YamlMap::ignore(const std::string& key) {
  entries_.push_back({key, nullptr, false});
  return *this;
}

void YamlMap::read() const {
  std::vector<std::string> keys;
  for (const Entry& e : entries_) keys.push_back(e.key);
  check_known_keys(node_, keys, ctx_);  // first: a misspelt key is named before a missing one
  for (const Entry& e : entries_) {
    if (!e.read) continue;
    const YAML::Node v = node_[e.key];  // const: looking up an absent key adds none
    if (v || e.always) e.read(v, e.key);
  }
}

}  // namespace s3m
