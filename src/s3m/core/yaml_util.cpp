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

void check_known_keys(const YAML::Node& node, const std::vector<std::string>& known, const std::string& ctx) {
  std::string list;
  for (const auto& k : known) list += (list.empty() ? "" : ", ") + k;
  // A section given as a value ('insert: nan', 'fusion: [1]'): without this, the yaml_get() calls
  // that follow would index a scalar and yaml-cpp would throw its own exception (found by fuzzing).
  if (node.IsScalar() || node.IsSequence())
    throw ParseError(ctx, node.Mark().line + 1,
                     node.IsScalar() ? "a value ('" + node.Scalar() + "') where a section is expected"
                                     : "a list where a section is expected",
                     "a map of keys 'name: value' (one of: " + list + ")");
  if (!node.IsMap()) return;
  for (const auto& kv : node) {
    // YAML allows sequences and maps as keys ('? [a, b]: 1'); no s3m config uses them.
    if (!kv.first.IsScalar())
      throw ParseError(ctx, kv.first.Mark().line + 1, "a key that is not a plain name", "keys like 'name: value'");
    const auto key = kv.first.Scalar();
    if (std::find(known.begin(), known.end(), key) == known.end()) {
      throw ParseError(ctx, kv.first.Mark().line + 1, "unknown key '" + key + "'", "one of: " + list);
    }
  }
}

}  // namespace s3m
