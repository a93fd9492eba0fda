#include "s3m/semantics/class_map.hpp"

#include <fstream>
#include <map>
#include <optional>

#include <opencv2/core.hpp>

#include "s3m/core/error.hpp"
#include "s3m/core/input_file.hpp"
#include "s3m/core/yaml_util.hpp"

namespace s3m::semantics {
namespace {

std::string trim(const std::string& s) {
  const auto b = s.find_first_not_of(" \t\r\n");
  if (b == std::string::npos) return "";
  return s.substr(b, s.find_last_not_of(" \t\r\n") - b + 1);
}

ClassId target_id(const ClassList& target, const std::string& name, const std::string& ctx, int line) {
  const int id = target.find(name);
  if (id < 0) {
    std::string names;
    for (const auto& c : target.all()) names += (names.empty() ? "" : ", ") + c.name;
    throw ParseError(ctx, line, "unknown project class '" + name + "'", "one of: " + names);
  }
  return static_cast<ClassId>(id);
}

}  // namespace

std::vector<std::string> read_class_names(const std::string& path) {
  std::ifstream in = open_input_file(path, "a readable text file, one class name per line");
  std::vector<std::string> names;
  std::string line;
  int line_no = 0;
  while (std::getline(in, line)) {
    ++line_no;
    const std::string t = trim(line);
    if (t.empty() || t[0] == '#') continue;
    const auto tab = t.find('\t');
    if (tab != std::string::npos) {
      const std::string id_str = trim(t.substr(0, tab));
      if (!id_str.empty() && id_str.find_first_not_of("0123456789") == std::string::npos) {
        const std::size_t id = id_str.size() > 6 ? 999999 : std::stoul(id_str);
        if (id > 65535)
          throw ParseError(path, line_no, "class id " + id_str + " too large", "an id <= 65535");
        if (names.size() <= id) names.resize(id + 1);
        if (!names[id].empty())
          throw ParseError(path, line_no, "class id " + id_str + " listed twice", "unique ids");
        names[id] = trim(t.substr(tab + 1));
        continue;
      }
      if (id_str == "id") continue;  // a TSV header line
    }
    names.push_back(t);
  }
  if (names.empty()) throw ParseError(path, 0, "class name list is empty", "at least one class name");
  return names;
}

ClassMap ClassMap::load(const std::string& yaml_path, const std::vector<std::string>& source_names,
                        const ClassList& target) {
  const YAML::Node root = load_yaml_file(yaml_path);
  try {
    return parse(root, yaml_path, source_names, target);
  } catch (const YAML::Exception& e) {  // an entry of the wrong shape
    throw ParseError(yaml_path, e.mark.line + 1, "bad class map entry: " + e.msg,
                     "the layout in class_map.hpp");
  }
}

ClassMap ClassMap::parse(const YAML::Node& root, const std::string& yaml_path,
                         const std::vector<std::string>& source_names, const ClassList& target) {
  std::string default_name = "other";
  int default_line = 0;
  YAML::Node map;
  std::optional<YAML::Node> palette;
  YamlMap keys(root, yaml_path);
  keys.ignore("source");  // which model's classes, for people
  keys.on("default", [&](const YAML::Node& v, const std::string& key) {
    default_name = yaml_as<std::string>(v, key, yaml_path);
    default_line = v.Mark().line + 1;
  });
  keys.always("map", [&](const YAML::Node& v, const std::string& key) {
    if (!v || !v.IsMap())
      throw ParseError(yaml_path, 0, "missing '" + key + "' section",
                       "map: {project_class: [source classes]}");
    map = v;
  });
  keys.on("palette", [&palette](const YAML::Node& v, const std::string&) { palette = v; });
  keys.read();

  std::map<std::string, int> source_index;
  for (std::size_t i = 0; i < source_names.size(); ++i)
    if (!source_names[i].empty()) source_index.emplace(source_names[i], static_cast<int>(i));

  ClassMap m;
  const ClassId def = target_id(target, default_name, yaml_path, default_line);
  m.table_.assign(source_names.size(), def);
  std::vector<bool> seen(source_names.size(), false);

  for (const auto& kv : map) {
    const int line = kv.first.Mark().line + 1;
    const ClassId to = target_id(target, kv.first.as<std::string>(), yaml_path, line);
    std::vector<std::string> from;
    if (kv.second.IsScalar())
      from.push_back(kv.second.as<std::string>());
    else if (kv.second.IsSequence())
      from = kv.second.as<std::vector<std::string>>();
    else
      throw ParseError(yaml_path, line, "bad entry", "a source class name or a list of them");
    for (const auto& name : from) {
      const auto it = source_index.find(name);
      if (it == source_index.end())
        throw ParseError(yaml_path, line, "source class '" + name + "' is not in the source class list",
                         "a name from the model's class list");
      if (seen[it->second])
        throw ParseError(yaml_path, line, "source class '" + name + "' mapped twice",
                         "each source class once");
      seen[it->second] = true;
      m.table_[it->second] = to;
    }
  }

  std::vector<ClassInfo> infos = target.all();
  if (palette) {
    for (const auto& kv : *palette) {
      const int line = kv.first.Mark().line + 1;
      const ClassId id = target_id(target, kv.first.as<std::string>(), yaml_path, line);
      std::vector<int> rgb;
      try {
        rgb = kv.second.as<std::vector<int>>();
      } catch (const YAML::Exception&) {
      }
      if (rgb.size() != 3 || rgb[0] < 0 || rgb[0] > 255 || rgb[1] < 0 || rgb[1] > 255 || rgb[2] < 0 ||
          rgb[2] > 255)
        throw ParseError(yaml_path, line, "bad palette colour", "[r, g, b] with values 0..255");
      infos[id].r = static_cast<std::uint8_t>(rgb[0]);
      infos[id].g = static_cast<std::uint8_t>(rgb[1]);
      infos[id].b = static_cast<std::uint8_t>(rgb[2]);
    }
  }
  m.target_ = ClassList(std::move(infos));
  return m;
}

ClassMap ClassMap::by_name(const std::vector<std::string>& source_names, const ClassList& target) {
  ClassMap m;
  m.target_ = target;
  const int other = target.find("other");
  const ClassId def = other >= 0 ? static_cast<ClassId>(other) : cls::kUnknown;
  for (const auto& n : source_names) {
    const int id = target.find(n);
    m.table_.push_back(id >= 0 ? static_cast<ClassId>(id) : def);
  }
  return m;
}

std::vector<int> ClassMap::sources_of(ClassId target_id) const {
  std::vector<int> out;
  for (std::size_t i = 0; i < table_.size(); ++i)
    if (table_[i] == target_id) out.push_back(static_cast<int>(i));
  return out;
}

cv::Mat ClassMap::apply(const cv::Mat& source_labels, ClassId out_of_range) const {
  require(source_labels.type() == CV_8UC1 || source_labels.type() == CV_16UC1,
          "ClassMap::apply: expected a CV_8UC1 or CV_16UC1 label image");
  cv::Mat src16;
  source_labels.convertTo(src16, CV_16UC1);
  cv::Mat out(src16.size(), CV_16UC1);
  for (int r = 0; r < src16.rows; ++r) {
    const auto* in = src16.ptr<std::uint16_t>(r);
    auto* o = out.ptr<ClassId>(r);
    for (int c = 0; c < src16.cols; ++c) o[c] = in[c] < table_.size() ? table_[in[c]] : out_of_range;
  }
  return out;
}

}  // namespace s3m::semantics
