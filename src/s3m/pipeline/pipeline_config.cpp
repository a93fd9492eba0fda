#include "s3m/pipeline/pipeline_config.hpp"

#include <cmath>
#include <filesystem>

#include <spdlog/spdlog.h>

#include "s3m/core/error.hpp"
#include "s3m/core/shipped_files.hpp"
#include "s3m/core/yaml_util.hpp"

namespace s3m::pipeline {
namespace {

std::string num(double v) { return std::to_string(v); }

// Reads an enum given as a string; the message lists the allowed spellings.
template <typename E>
void read_enum(const YAML::Node& n, const std::string& key, E& out,
               const std::vector<std::pair<std::string, E>>& names, const std::string& ctx) {
  if (!n[key]) return;
  std::string s;
  yaml_get(n, key, s, ctx);
  std::string allowed;
  for (const auto& [name, value] : names) {
    if (name == s) {
      out = value;
      return;
    }
    allowed += (allowed.empty() ? "" : " | ") + name;
  }
  throw ParseError(ctx, n[key].Mark().line + 1, "bad value '" + s + "' for '" + key + "'", allowed);
}

// A section must be a map; returns an empty node when absent.
YAML::Node section(const YAML::Node& root, const std::string& key, const std::string& ctx) {
  const YAML::Node n = root[key];
  if (n && !n.IsMap())
    throw ParseError(ctx, n.Mark().line + 1, "section '" + key + "' is not a map", "key: value pairs");
  return n;
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

void load_dataset(const YAML::Node& n, DatasetConfig& c, const std::string& ctx) {
  check_known_keys(n, {"camera", "max_dt_s", "depth_registration", "max_unreadable_in_a_row"}, ctx);
  yaml_get(n, "camera", c.camera, ctx);
  yaml_get(n, "max_dt_s", c.max_dt_s, ctx);
  yaml_get(n, "depth_registration", c.depth_registration, ctx);
  yaml_get(n, "max_unreadable_in_a_row", c.max_unreadable_in_a_row, ctx);
}

void load_cloud(const YAML::Node& n, CloudConfig& c, const std::string& ctx) {
  check_known_keys(
      n, {"min_depth_m", "max_depth_m", "pixel_stride", "keyframe_voxel_m", "kept_clouds_budget_mb"}, ctx);
  yaml_get(n, "min_depth_m", c.min_depth_m, ctx);
  yaml_get(n, "max_depth_m", c.max_depth_m, ctx);
  yaml_get(n, "pixel_stride", c.pixel_stride, ctx);
  yaml_get(n, "keyframe_voxel_m", c.keyframe_voxel_m, ctx);
  yaml_get(n, "kept_clouds_budget_mb", c.kept_clouds_budget_mb, ctx);
}

void load_threads(const YAML::Node& n, ThreadingConfig& c, const std::string& ctx) {
  check_known_keys(n, {"deterministic", "queue_capacity"}, ctx);
  yaml_get(n, "deterministic", c.deterministic, ctx);
  yaml_get(n, "queue_capacity", c.queue_capacity, ctx);
}

void load_flow(const YAML::Node& n, FlowConfig& c, const std::string& ctx) {
  check_known_keys(n, {"integrate", "segment", "final_reintegration"}, ctx);
  read_enum(n, "integrate", c.integrate,
            {{"keyframes", IntegrateMode::kKeyframes}, {"all_frames", IntegrateMode::kAllFrames}}, ctx);
  read_enum(n, "segment", c.segment,
            {{"integrated", SegmentMode::kIntegrated}, {"all_frames", SegmentMode::kAllFrames}}, ctx);
  yaml_get(n, "final_reintegration", c.final_reintegration, ctx);
}

void load_segmenter(const YAML::Node& n, SegmenterConfig& c, const std::string& ctx) {
  check_known_keys(n, {"type", "model", "model_dir", "top_k", "oracle"}, ctx);
  yaml_get(n, "type", c.type, ctx);
  yaml_get(n, "model", c.model, ctx);
  yaml_get(n, "model_dir", c.model_dir, ctx);
  yaml_get(n, "top_k", c.top_k, ctx);
  if (n["oracle"]) c.oracle = semantics::load_oracle_config(n["oracle"], ctx);
}

void load_eval(const YAML::Node& n, EvalConfig& c, const std::string& ctx) {
  check_known_keys(
      n, {"rpe_delta_s", "gt_max_dt_s", "align", "plots", "reprojection_every_n", "reprojection_max_frames"},
      ctx);
  yaml_get(n, "rpe_delta_s", c.rpe_delta_s, ctx);
  yaml_get(n, "gt_max_dt_s", c.gt_max_dt_s, ctx);
  yaml_get(n, "align", c.align, ctx);
  yaml_get(n, "plots", c.plots, ctx);
  yaml_get(n, "reprojection_every_n", c.reprojection_every_n, ctx);
  yaml_get(n, "reprojection_max_frames", c.reprojection_max_frames, ctx);
}

}  // namespace

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

PipelineConfig pipeline_config_from_yaml(const YAML::Node& root, const std::string& path) {
  PipelineConfig c;
  c.source = path;
  if (!root || root.IsNull()) return c;  // an empty preset means "all defaults"
  if (!root.IsMap())
    throw ParseError(path, 1, "top level is not a map", "sections such as 'cloud:', 'slam:'");
  check_known_keys(
      root, {"dataset", "slam", "loop_closing", "cloud", "threads", "flow", "eval", "map", "segmenter"},
      path);
  if (const auto n = section(root, "dataset", path)) load_dataset(n, c.dataset, path);
  if (const auto n = section(root, "slam", path)) c.slam = slam::slam_config_from_yaml(n, path);
  if (const auto n = section(root, "loop_closing", path))
    slam::read_loop_closing(n, c.slam.loop_closing, path);
  if (const auto n = section(root, "cloud", path)) load_cloud(n, c.cloud, path);
  if (const auto n = section(root, "threads", path)) load_threads(n, c.threads, path);
  if (const auto n = section(root, "flow", path)) load_flow(n, c.flow, path);
  if (const auto n = section(root, "eval", path)) load_eval(n, c.eval, path);
  if (const auto n = section(root, "map", path)) c.map = mapping::load_mapping_config(n, path);
  if (const auto n = section(root, "segmenter", path)) load_segmenter(n, c.segmenter, path);
  // A relative camera file is relative to the preset (presets live next to their camera files).
  const auto& cam = c.dataset.camera;
  if (!cam.empty() && cam.find(".yaml") != std::string::npos && std::filesystem::path(cam).is_relative())
    c.dataset.camera = preset_relative(path, cam);
  validate_in(c.dataset, path, "dataset");
  validate_in(c.slam.loop_closing, path, "loop_closing");
  validate_in(c.slam, path, "slam");
  validate_in(c.cloud, path, "cloud");
  validate_in(c.threads, path, "threads");
  validate_in(c.flow, path, "flow");
  validate_in(c.eval, path, "eval");
  validate_in(c.map, path, "map");
  // Model and vocabulary paths in a preset are relative to the preset, like camera files.
  for (std::string* p : {&c.segmenter.model, &c.segmenter.model_dir, &c.slam.loop_closing.vocabulary})
    if (!p->empty() && std::filesystem::path(*p).is_relative()) *p = preset_relative(path, *p);
  validate_in(c.segmenter, path, "segmenter");
  return c;
}

}  // namespace s3m::pipeline
