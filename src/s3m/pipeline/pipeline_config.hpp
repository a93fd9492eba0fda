#pragma once
// Configuration of the end-to-end pipeline: its own parameters plus the configs of the modules it
// wires together. Loaded from a YAML preset in config/ (see config/README.md for every key);
// keys absent from the file keep the defaults below, unknown keys are refused with file and line.
// The robot trajectory uses the SLAM section's calibration: T_w_r = T_w_c * slam.T_c_r.
#include <set>
#include <string>
#include <vector>

#include <yaml-cpp/yaml.h>

#include "s3m/core/se3.hpp"
#include "s3m/mapping/fusion.hpp"
#include "s3m/mapping/insert.hpp"
#include "s3m/mapping/mapping_config.hpp"
#include "s3m/semantics/oracle_segmenter.hpp"
#include "s3m/slam/slam_config.hpp"

namespace s3m::pipeline {

// Which frames go into the semantic map.
enum class IntegrateMode {
  kKeyframes,  // only SLAM keyframes (the paper's choice; keeps the map consistent with loop closures)
  kAllFrames,  // every tracked frame (denser evidence; clouds of non-keyframes are not re-integrated)
};

// Which frames are segmented.
enum class SegmentMode {
  kAuto,        // s3m run: every frame when the dataset has ground-truth labels to score them, else
                // only the integrated ones; a Pipeline built without a dataset: as kIntegrated
  kIntegrated,  // only frames that go into the map (cheapest)
  kAllFrames,   // every frame (needed for per-frame segmentation mIoU on every frame)
};

struct DatasetConfig {
  std::string camera;      // camera preset ("tum_fr1") or YAML file; empty = <dataset>/camera.yaml
  double max_dt_s = 0.02;  // max rgb/depth timestamp gap when associating by nearest time [s]
  // "auto" | "registered" | "unregistered": whether depth pixels are the colour pixels' (auto:
  // checked on a few frames before the first; unregistered_depth.hpp).
  std::string depth_registration = "auto";
  // A frame whose image files cannot be read (truncated, corrupt, wrong size) is skipped with a
  // warning naming the file, as a camera drops a frame, and listed in metrics.json; more than this
  // many in a row is a broken recording: the run stops, after writing the outputs of the frames
  // before. 0 = stop at the first.
  int max_unreadable_in_a_row = 10;
  void validate() const;
};

struct CloudConfig {
  double min_depth_m = 0.2;  // pixels closer than this are dropped before back-projection [m]
  double max_depth_m = 4.0;  // pixels farther than this are dropped (sensor noise grows with z^2) [m]
  int pixel_stride = 2;      // back-project every n-th pixel in u and v (1 = all) [px]
  // Keyframe clouds kept for re-integration after loop closure are voxel-downsampled to this size;
  // 0 = the map resolution. What is kept is exactly what was inserted, so a rebuild is exact. [m]
  double keyframe_voxel_m = 0.0;
  // Memory budget of the kept clouds: beyond it the most redundant ones are dropped (see
  // keyframe_store.hpp); 0 = keep every cloud (memory grows with the number of integrated frames). [MB]
  double kept_clouds_budget_mb = 256.0;
  void validate() const;
};

struct ThreadingConfig {
  bool deterministic = false;  // single thread, identical output run to run (tests, debugging)
  int queue_capacity = 4;      // frames buffered between stages; a full queue blocks the producer
  void validate() const;
};

struct FlowConfig {
  IntegrateMode integrate = IntegrateMode::kKeyframes;
  SegmentMode segment = SegmentMode::kAuto;
  // Re-integrate all kept keyframe clouds with the final optimised keyframe poses at the end, so the
  // saved map agrees with the saved (bundle-adjusted) keyframe trajectory.
  bool final_reintegration = true;
  void validate() const;
};

struct EvalConfig {
  double rpe_delta_s = 1.0;   // RPE over this time delta [s]
  double gt_max_dt_s = 0.02;  // max timestamp gap estimate <-> ground truth [s]
  std::string align = "se3";  // trajectory alignment before ATE: se3 | sim3 | none
  bool plots = true;          // write OUT/report/ (PNG plots + report.html) via tools/*.py
  // Map labels projected back into segmented frames with ground truth (reprojection.hpp): every
  // n-th such frame is kept (its argmax, 2 bytes/px), at most max_frames (0 = off) [frames].
  int reprojection_every_n = 10;
  int reprojection_max_frames = 30;
  void validate() const;
};

// The `dynamic:` section: things that move (people) in a scene SLAM and the map otherwise assume
// static. Off by default (`s3m run --dynamic`), so runs of static scenes map and track as before
// (a standing person stays in the map).
struct DynamicConfig {
  bool enabled = false;
  // Classes that move (names of the indoor class list). Their voxels are not made occupied (rays
  // still clear the space in front of them), unless keep_in_map.
  std::vector<std::string> classes{"person"};
  bool keep_in_map = false;  // `s3m run --keep-dynamic`: map them like any other class
  // Tracking uses no keypoint where the last segmented frame's dynamic pixels, moved into the
  // frame by their depth and the predicted pose, fall (dynamic_mask.hpp). Needs a segmenter.
  bool mask_tracking = true;
  // The warped pixels are grown by this much: a person moves between the segmented frame and the
  // tracked one [px].
  int mask_margin_px = 4;
  // Where the tracking mask comes from: "segmented" (above), or "labels": the frame's own
  // ground-truth label image (simulator sequences), the best any segmentation could do, to
  // evaluate the rest of the method.
  std::string mask_source = "segmented";
  // Pixels this close to a dynamic pixel are left out of the map too (borders of segments and of
  // depth mix a person with what is behind) [px].
  int map_margin_px = 4;
  void validate() const;
  std::vector<ClassId> class_ids() const;  // the ids of `classes` in the indoor class list
  // What the map leaves out: class_ids() when enabled and not keep_in_map, else nothing.
  std::vector<ClassId> map_exclusions() const {
    return enabled && !keep_in_map ? class_ids() : std::vector<ClassId>{};
  }
  bool masks_tracking() const { return enabled && mask_tracking; }
};

// The `map:` section of a preset is mapping::MappingConfig (resolution_m, occupancy, fusion, insert).
using MapConfig = mapping::MappingConfig;

// The `segmenter:` section. `s3m run --segmenter` overrides type/model.
struct SegmenterConfig {
  // auto: the oracle on a simulator sequence, the shipped real-image model on anything else
  // (pipeline::choose_segmenter); onnx | oracle | none: as said.
  std::string type = "auto";
  std::string model;      // onnx: model card (.yaml) or a folder holding one; relative to the preset
  std::string model_dir;  // onnx: folder with the model files when the card lives elsewhere
  int top_k = 3;          // oracle: labels per pixel (an ONNX model card carries its own)
  semantics::OracleNoiseConfig oracle;  // `oracle:` noise model (keys of semantics::OracleNoiseConfig)
  void validate() const;
};

struct PipelineConfig {
  DatasetConfig dataset;
  CloudConfig cloud;
  ThreadingConfig threads;
  FlowConfig flow;
  EvalConfig eval;
  // `slam:` section (s3m::slam keys), including the calibration T_c_r; slam.loop_closing is the
  // `loop_closing:` section (slam::read_loop_closing; a relative vocabulary is relative to the preset).
  slam::SlamConfig slam;
  MapConfig map;
  DynamicConfig dynamic;
  SegmenterConfig segmenter;
  // Named overlays (config/overlays/NAME.yaml, config_overlays.hpp) applied beneath the keys this
  // config writes: those a preset lists under `overlays:`, then those an automatic decision chose.
  std::vector<std::string> overlays;
  std::string source;  // file the config was loaded from ("" = defaults), for messages
  // Keys the preset and the command line set, dotted ("slam.features.depth_window_px"), with those
  // of the overlays the preset lists: automatic decisions leave them as they are.
  std::set<std::string> written;
  void validate() const;
};

// Its YAML keys with the members they fill (core/config_table.hpp): the sections above, each with
// its own table, and `overlays`.
void fields(config::FieldVisitor& v, PipelineConfig& c);

// Records that the command line set `key` (dotted; must be a key of the table), so that automatic
// decisions leave it as set.
void mark_written(PipelineConfig& c, const std::string& key);

// Loads and validates a preset. Errors name the file, the line and what was expected. The overlays
// it lists are applied to the keys it does not write.
PipelineConfig load_pipeline_config(const std::string& path);
// The same from an already parsed document (e.g. a preset merged with ROS parameters); `path`
// names it in messages and anchors relative camera/model paths (its folder; "" = the working dir).
PipelineConfig pipeline_config_from_yaml(const YAML::Node& root, const std::string& path);

}  // namespace s3m::pipeline
