#pragma once
// Mapping a model's (or a dataset's) class list onto the project's indoor classes, many-to-one.
//
// YAML format (config/classmaps/*.yaml):
//   source: free text naming the source class list
//   default: other            # project class for source classes not listed (usually "other")
//   map:                      # project class: [source class names...]
//     wall: [wall, column]
//     table: [table, desk, coffee table]
//   palette:                  # optional colour overrides for project classes, [r, g, b]
//     wall: [120, 120, 120]
// Source names must exist in the source class list (typos are errors), each at most once.
// Mapping to "unknown" is allowed (e.g. a dataset's "unlabeled").
#include <string>
#include <vector>

#include <opencv2/core.hpp>
#include <yaml-cpp/yaml.h>

#include "s3m/core/classes.hpp"

namespace s3m::semantics {

// Source class names. Two line formats: "name" (index = running line number among non-comment
// lines) or "<id><TAB>name" (explicit id, gaps allowed -> empty names). '#' starts a comment line.
// Names may contain spaces ("chest of drawers").
std::vector<std::string> read_class_names(const std::string& path);

class ClassMap {
 public:
  ClassMap() = default;
  // From a YAML map file; source_names[i] = name of source class i.
  static ClassMap load(const std::string& yaml_path, const std::vector<std::string>& source_names,
                       const ClassList& target = indoor_classes());
  // Identity by name: a source class named like a project class maps to it, others to "other".
  static ClassMap by_name(const std::vector<std::string>& source_names, const ClassList& target = indoor_classes());

  std::size_t source_size() const { return table_.size(); }
  ClassId operator[](std::size_t source_id) const { return table_.at(source_id); }
  const std::vector<ClassId>& table() const { return table_; }
  // Target list with the palette overrides applied (for colourising).
  const ClassList& target() const { return target_; }
  // Source ids mapped to a project class (empty if none).
  std::vector<int> sources_of(ClassId target_id) const;
  // Applies the map to a source label image (CV_8UC1 or CV_16UC1) -> CV_16UC1 project ids.
  // Source ids beyond the list map to `out_of_range` (default: unknown).
  cv::Mat apply(const cv::Mat& source_labels, ClassId out_of_range = cls::kUnknown) const;

 private:
  static ClassMap parse(const YAML::Node& root, const std::string& yaml_path, const std::vector<std::string>& source_names,
                        const ClassList& target);
  std::vector<ClassId> table_;  // source id -> project id
  ClassList target_;
};

}  // namespace s3m::semantics
