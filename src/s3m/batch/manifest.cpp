// The batch manifest reader (manifest.hpp).
#include "s3m/batch/manifest.hpp"

#include <cctype>
#include <filesystem>
#include <set>

#include "s3m/core/error.hpp"
#include "s3m/core/yaml_util.hpp"

namespace s3m::batch {
namespace fs = std::filesystem;

namespace {

std::string absolute_from(const fs::path& base, const std::string& p) {
  if (p.empty()) return p;
  return fs::absolute(base / p).lexically_normal().string();
}

// The run settings' keys on a YamlMap: into `s`, paths relative to `base`.
void settings_keys(YamlMap& m, RunSettings& s, const fs::path& base) {
  m.on("config",
       [&s, base](const YAML::Node& v, const std::string& k) {
         s.config = absolute_from(base, yaml_as<std::string>(v, k, "manifest"));
       })
      .get("segmenter", s.segmenter)
      .get("deterministic", s.deterministic)
      .get("max_frames", s.max_frames);
}

bool plain_name(const std::string& n) {
  if (n.empty() || n == "." || n == "..") return false;
  for (const char c : n)
    if (!std::isalnum(static_cast<unsigned char>(c)) && c != '.' && c != '_' && c != '-') return false;
  return true;
}

Recording read_recording(const YAML::Node& node, const RunSettings& defaults, const fs::path& base,
                         const std::string& file) {
  Recording r;
  r.run = defaults;
  YamlMap m(node, file);
  m.always("path", [&](const YAML::Node& v, const std::string& k) {
     if (!v)
       throw ParseError(file, node.Mark().line + 1, "a recording without 'path'", "path: FOLDER_OR_BAG");
     r.path = absolute_from(base, yaml_as<std::string>(v, k, file));
   }).get("name", r.name);
  settings_keys(m, r.run, base);
  m.read();
  if (r.name.empty()) r.name = fs::path(r.path).filename().replace_extension().string();
  if (!plain_name(r.name))
    throw ParseError(file, node.Mark().line + 1, "recording name '" + r.name + "' cannot name a folder",
                     "letters, digits, '.', '_' and '-' (set 'name:')");
  return r;
}

}  // namespace

Manifest load_manifest(const std::string& path) {
  const YAML::Node root = load_yaml_file(path);
  Manifest out;
  out.file = fs::absolute(path).lexically_normal().string();
  const fs::path base = fs::path(out.file).parent_path();
  RunSettings defaults;
  YAML::Node recordings;
  bool merge_config_set = false;
  YamlMap top(root, path);
  top.on("defaults",
         [&](const YAML::Node& v, const std::string&) {
           YamlMap d(v, path);
           settings_keys(d, defaults, base);
           d.read();
         })
      .always("recordings",
              [&](const YAML::Node& v, const std::string&) {
                if (!v || !v.IsSequence() || v.size() == 0)
                  throw ParseError(path, root.Mark().line + 1, "no recordings",
                                   "recordings: a list of {path: ...} entries");
                recordings = v;
              })
      .on("merge", [&](const YAML::Node& v, const std::string&) {
        YamlMap mm(v, path);
        mm.on("config", [&](const YAML::Node& c, const std::string& k) {
          out.merge_config = absolute_from(base, yaml_as<std::string>(c, k, path));
          merge_config_set = true;
        });
        mm.read();
      });
  top.read();
  std::set<std::string> names;
  for (const YAML::Node& node : recordings) {
    Recording r = read_recording(node, defaults, base, path);
    if (!names.insert(r.name).second)
      throw ParseError(path, node.Mark().line + 1, "a second recording named '" + r.name + "'",
                       "a unique name per recording (set 'name:')");
    out.recordings.push_back(std::move(r));
  }
  if (!merge_config_set) out.merge_config = defaults.config;
  return out;
}

}  // namespace s3m::batch
