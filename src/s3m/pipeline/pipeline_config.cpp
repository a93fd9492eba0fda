#include "s3m/pipeline/pipeline_config.hpp"

#include <algorithm>
#include <cmath>
#include <filesystem>

#include <spdlog/spdlog.h>

#include "s3m/core/config_table.hpp"
#include "s3m/core/error.hpp"
#include "s3m/core/shipped_files.hpp"
#include "s3m/core/yaml_util.hpp"
#include "s3m/pipeline/config_overlays.hpp"

namespace s3m::pipeline {
namespace {

std::string num(double v) { return std::to_string(v); }

// A top-level section must be a map (a scalar or list there is a typo of the section's keys);
// unknown keys are left to the reader, which lists the known ones.
void require_sections_are_maps(const YAML::Node& root, const std::vector<std::string>& sections,
                               const std::string& ctx) {
  for (const auto& kv : root) {
    const std::string key = kv.first.IsScalar() ? kv.first.Scalar() : "";
    if (std::find(sections.begin(), sections.end(), key) != sections.end() && !kv.second.IsMap())
      throw ParseError(ctx, kv.second.Mark().line + 1, "section '" + key + "' is not a map",
                       "key: value pairs");
  }
}

// Wraps validate() so a bad value names the config file (validate() alone cannot know it).
template <typename C>
void validate_in(const C& c, const std::string& ctx, const std::string& sec) {
  try {
    c.validate();
  } catch (const ParseError&) {
    throw;
  } catch (const Error& e) {
    throw ParseError(ctx, 0, "section '" + sec + "': " + e.what(), "a valid value");
  }
}

}  // namespace

void fields(config::FieldVisitor& v, DatasetConfig& c) {
  v("camera", c.camera);
  v("max_dt_s", c.max_dt_s);
  v("depth_registration", c.depth_registration);
  v("max_unreadable_in_a_row", c.max_unreadable_in_a_row);
}

void fields(config::FieldVisitor& v, CloudConfig& c) {
  v("min_depth_m", c.min_depth_m);
  v("max_depth_m", c.max_depth_m);
  v("pixel_stride", c.pixel_stride);
  v("keyframe_voxel_m", c.keyframe_voxel_m);
  v("kept_clouds_budget_mb", c.kept_clouds_budget_mb);
}

void fields(config::FieldVisitor& v, ThreadingConfig& c) {
  v("deterministic", c.deterministic);
  v("queue_capacity", c.queue_capacity);
}

void fields(config::FieldVisitor& v, FlowConfig& c) {
  v("integrate", config::choice(c.integrate, {{"keyframes", IntegrateMode::kKeyframes},
                                              {"all_frames", IntegrateMode::kAllFrames}}));
  v("segment", config::choice(c.segment, {{"auto", SegmentMode::kAuto},
                                          {"integrated", SegmentMode::kIntegrated},
                                          {"all_frames", SegmentMode::kAllFrames}}));
  v("final_reintegration", c.final_reintegration);
}

void fields(config::FieldVisitor& v, EvalConfig& c) {
  v("rpe_delta_s", c.rpe_delta_s);
  v("gt_max_dt_s", c.gt_max_dt_s);
  v("align", c.align);
  v("plots", c.plots);
  v("reprojection_every_n", c.reprojection_every_n);
  v("reprojection_max_frames", c.reprojection_max_frames);
}

void fields(config::FieldVisitor& v, SegmenterConfig& c) {
  v("type", c.type);
  v("model", c.model);
  v("model_dir", c.model_dir);
  v("top_k", c.top_k);
  v("oracle", c.oracle);
}

void fields(config::FieldVisitor& v, PipelineConfig& c) {
  v("dataset", c.dataset);
  v("slam", c.slam);
  v("loop_closing", c.slam.loop_closing);
  v("cloud", c.cloud);
  v("threads", c.threads);
  v("flow", c.flow);
  v("eval", c.eval);
  v("map", c.map);
  v("dynamic", c.dynamic);
  v("segmenter", c.segmenter);
  v("overlays", c.overlays);
}

void mark_written(PipelineConfig& c, const std::string& key) {
  const auto all = config::values(c);
  require(std::any_of(all.begin(), all.end(), [&](const auto& kv) { return kv.first == key; }),
          "mark_written: '" + key + "' is not a config key");
  c.written.insert(key);
}

void SegmenterConfig::validate() const {
  require(type == "auto" || type == "onnx" || type == "oracle" || type == "none",
          "segmenter.type must be auto | onnx | oracle | none (got '" + type + "')");
  require(type != "onnx" || !model.empty(), "segmenter.model (a model card) is required for type onnx");
  require(top_k >= 1 && top_k <= mapping::kMaxLabels,
          "segmenter.top_k must be in 1.." + std::to_string(mapping::kMaxLabels));
  oracle.validate();
}

void DatasetConfig::validate() const {
  require(std::isfinite(max_dt_s) && max_dt_s > 0 && max_dt_s < 1.0,
          "dataset.max_dt_s must be in (0, 1) s (got " + num(max_dt_s) + ")");
  require(depth_registration == "auto" || depth_registration == "registered" ||
              depth_registration == "unregistered",
          "dataset.depth_registration must be auto | registered | unregistered (got '" + depth_registration +
              "')");
  require(max_unreadable_in_a_row >= 0, "dataset.max_unreadable_in_a_row must be >= 0 (got " +
                                            std::to_string(max_unreadable_in_a_row) + ")");
}

void CloudConfig::validate() const {
  require(std::isfinite(min_depth_m) && min_depth_m >= 0,
          "cloud.min_depth_m must be >= 0 m (got " + num(min_depth_m) + ")");
  require(std::isfinite(max_depth_m) && max_depth_m > min_depth_m && max_depth_m <= 100,
          "cloud.max_depth_m must be in (min_depth_m, 100] m (got " + num(max_depth_m) + ")");
  require(pixel_stride >= 1 && pixel_stride <= 32,
          "cloud.pixel_stride must be in 1..32 px (got " + std::to_string(pixel_stride) + ")");
  require(std::isfinite(keyframe_voxel_m) && keyframe_voxel_m >= 0 && keyframe_voxel_m <= 1.0,
          "cloud.keyframe_voxel_m must be in [0, 1] m (got " + num(keyframe_voxel_m) + ")");
  require(std::isfinite(kept_clouds_budget_mb) && kept_clouds_budget_mb >= 0 && kept_clouds_budget_mb <= 1e6,
          "cloud.kept_clouds_budget_mb must be in [0, 1e6] MB, 0 = unlimited (got " +
              num(kept_clouds_budget_mb) + ")");
}

void ThreadingConfig::validate() const {
  require(queue_capacity >= 1 && queue_capacity <= 256,
          "threads.queue_capacity must be in 1..256 frames (got " + std::to_string(queue_capacity) + ")");
}

void FlowConfig::validate() const {}

void fields(config::FieldVisitor& v, DynamicConfig& c) {
  v("enabled", c.enabled);
  v("classes", c.classes);
  v("keep_in_map", c.keep_in_map);
  v("mask_tracking", c.mask_tracking);
  v("mask_margin_px", c.mask_margin_px);
  v("mask_source", c.mask_source);
  v("map_margin_px", c.map_margin_px);
}

void DynamicConfig::validate() const {
  class_ids();  // every name known
  require(mask_margin_px >= 0 && mask_margin_px <= 200,
          "dynamic.mask_margin_px must be in [0, 200] px (got " + std::to_string(mask_margin_px) + ")");
  require(map_margin_px >= 0 && map_margin_px <= 50,
          "dynamic.map_margin_px must be in [0, 50] px (got " + std::to_string(map_margin_px) + ")");
  require(mask_source == "segmented" || mask_source == "labels",
          "dynamic.mask_source must be segmented | labels (got '" + mask_source + "')");
}

std::vector<ClassId> DynamicConfig::class_ids() const {
  std::vector<ClassId> ids;
  for (const std::string& name : classes) {
    const int id = indoor_classes().find(name);
    require(id > 0, "dynamic.classes: '" + name + "' is not a class of the indoor class list (classes.txt)");
    ids.push_back(static_cast<ClassId>(id));
  }
  return ids;
}

void EvalConfig::validate() const {
  require(std::isfinite(rpe_delta_s) && rpe_delta_s > 0,
          "eval.rpe_delta_s must be > 0 s (got " + num(rpe_delta_s) + ")");
  require(std::isfinite(gt_max_dt_s) && gt_max_dt_s > 0,
          "eval.gt_max_dt_s must be > 0 s (got " + num(gt_max_dt_s) + ")");
  require(align == "se3" || align == "sim3" || align == "none",
          "eval.align must be se3 | sim3 | none (got '" + align + "')");
  require(reprojection_every_n >= 1,
          "eval.reprojection_every_n must be >= 1 frame (got " + std::to_string(reprojection_every_n) + ")");
  require(reprojection_max_frames >= 0 && reprojection_max_frames <= 10000,
          "eval.reprojection_max_frames must be in [0, 10000] frames (got " +
              std::to_string(reprojection_max_frames) + ")");
}

void PipelineConfig::validate() const {
  dataset.validate();
  slam.validate();
  cloud.validate();
  threads.validate();
  flow.validate();
  eval.validate();
  map.validate();
  dynamic.validate();
  segmenter.validate();
}

namespace {

// A relative path in a preset names a file next to the preset. A shipped preset copied elsewhere to
// be edited (the usual way to make one's own) still means the shipped file ("../models/x.yaml" seen
// from config/), so when nothing is beside the copy, the shipped tree's file is used, and said so.
std::string preset_relative(const std::string& preset, const std::string& value) {
  namespace fs = std::filesystem;
  const fs::path beside = (fs::path(preset).parent_path() / value).lexically_normal();
  const auto exists = [](const fs::path& p) { return fs::exists(p) || fs::exists(p.string() + ".yaml"); };
  if (exists(beside)) return beside.string();
  const fs::path shipped = shipped_file((fs::path("config") / value).lexically_normal().string());
  if (!exists(shipped)) return beside.string();  // the error names where it was expected
  spdlog::info("{}: '{}' is not next to this preset; using the shipped {}", preset, value, shipped.string());
  return shipped.string();
}

}  // namespace

PipelineConfig load_pipeline_config(const std::string& path) {
  return pipeline_config_from_yaml(load_yaml_file(path), path);
}

namespace {

// The keys root writes, then the overlays it lists (a preset's own choice: their keys count as
// written too).
void read_keys(const YAML::Node& root, PipelineConfig& c, const std::string& path) {
  std::vector<std::string> sections = config::keys(config::table_of(c));
  sections.erase(std::remove(sections.begin(), sections.end(), "overlays"), sections.end());
  require_sections_are_maps(root, sections, path);
  const config::ReadKeys read = config::read(root, config::table_of(c), path);
  c.written.insert(read.set.begin(), read.set.end());
  for (const std::string& name : std::vector<std::string>(c.overlays)) {
    try {
      const OverlayResult o = apply_overlay(c, name, "listed in " + (path.empty() ? "the config" : path));
      c.written.insert(o.set.begin(), o.set.end());
    } catch (const ParseError&) {
      throw;
    } catch (const Error& e) {  // an unknown name
      throw ParseError(path, root["overlays"].Mark().line + 1, e.what());
    }
  }
}

// Camera files, models and the vocabulary named in a preset are relative to the preset (presets
// live next to their camera files); a camera without ".yaml" is a preset name.
void resolve_relative_paths(PipelineConfig& c, const std::string& path) {
  const auto relative = [](const std::string& p) {
    return !p.empty() && std::filesystem::path(p).is_relative();
  };
  if (relative(c.dataset.camera) && c.dataset.camera.find(".yaml") != std::string::npos)
    c.dataset.camera = preset_relative(path, c.dataset.camera);
  for (std::string* p : {&c.segmenter.model, &c.segmenter.model_dir, &c.slam.loop_closing.vocabulary})
    if (relative(*p)) *p = preset_relative(path, *p);
}

}  // namespace

PipelineConfig pipeline_config_from_yaml(const YAML::Node& root, const std::string& path) {
  PipelineConfig c;
  c.source = path;
  if (!root || root.IsNull()) return c;  // an empty preset means "all defaults"
  if (!root.IsMap())
    throw ParseError(path, 1, "top level is not a map", "sections such as 'cloud:', 'slam:'");
  read_keys(root, c, path);
  resolve_relative_paths(c, path);
  validate_in(c.dataset, path, "dataset");
  validate_in(c.slam.loop_closing, path, "loop_closing");
  validate_in(c.slam, path, "slam");
  validate_in(c.cloud, path, "cloud");
  validate_in(c.threads, path, "threads");
  validate_in(c.flow, path, "flow");
  validate_in(c.eval, path, "eval");
  validate_in(c.map, path, "map");
  validate_in(c.dynamic, path, "dynamic");
  validate_in(c.segmenter, path, "segmenter");
  return c;
}

}  // namespace s3m::pipeline
