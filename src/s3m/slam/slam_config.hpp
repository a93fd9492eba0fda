#pragma once
// All SLAM settings in one plain struct with defaults; loadable from YAML (config/slam_*.yaml).
#include <string>

#include <yaml-cpp/yaml.h>

#include "s3m/core/se3.hpp"
#include "s3m/features/frame_features.hpp"
#include "s3m/slam/local_mapping/local_mapper.hpp"
#include "s3m/slam/loop/loop_closer.hpp"
#include "s3m/slam/tracking/reloc.hpp"
#include "s3m/slam/tracking/tracker.hpp"

namespace s3m::config {
class FieldVisitor;
}

namespace s3m::slam {

// Place recognition: loop closing and relocalisation. Both need a bag-of-words vocabulary, which
// the caller loads from `vocabulary` and hands to System (pipeline::load_vocabulary).
struct LoopClosingConfig {
  bool enabled = true;         // detect and close loops
  bool relocalisation = true;  // relocalise LOST frames against the whole map
  std::string vocabulary;      // vocabulary file ("": the shipped vocab/orb_k10_l5.bin)
  LoopConfig loop;
  RelocConfig reloc;
  bool any() const { return enabled || relocalisation; }
  void validate() const;
};

struct SlamConfig {
  features::FeatureConfig features;
  TrackerConfig tracker;
  MapperConfig mapper;
  LoopClosingConfig loop_closing;  // a pipeline preset's `loop_closing:` section
  SE3 T_c_r = SE3::Identity();     // robot (body) frame to camera frame: T_w_r = T_w_c * T_c_r
  bool threaded = false;           // tracking and local mapping in separate threads
  // Bound of the two queues between tracking and local mapping (threaded mode). Tracking keeps at
  // most tracker.max_pending_keyframes + 1 keyframes unanswered, plus one relocalisation query:
  // validate() requires room for that, so neither thread can block the other for good.
  int queue_capacity = 5;
  // Threaded mode: tracking of a frame takes the keyframes it sent up to this many frames earlier,
  // waiting for them if local mapping has not finished, and no others. The result then does not
  // depend on timing: every run gives the same trajectory, and 1 (the default) exactly the
  // single-thread one, with local mapping running while the next frame's features are extracted
  // and the rest of the pipeline works. 0: take whatever has arrived (at most
  // tracker.max_pending_keyframes behind; faster, but the trajectory changes with the machine's
  // load and is less accurate; see docs/DECISIONS.md, "Threaded mode: mapping lag").
  int mapping_lag_frames = 1;

  void validate() const;
};

// The YAML keys of the `slam:` and `loop_closing:` sections, with the members they fill
// (core/config_table.hpp; the tables of the member structs are in slam_config.cpp).
void fields(config::FieldVisitor& v, SlamConfig& c);
void fields(config::FieldVisitor& v, LoopClosingConfig& c);

// Reads a SlamConfig from a YAML node (sections: features/orb, tracker, mapper/ba, calibration,
// threaded). Absent keys keep their defaults; unknown keys are errors naming the file and line.
// T_c_r is given as `T_c_r: {t: [x, y, z], q: [qx, qy, qz, qw]}` (metres, unit quaternion).
// The loop_closing member comes from its own section (read_loop_closing).
SlamConfig slam_config_from_yaml(const YAML::Node& node, const std::string& ctx);
// Reads a `loop_closing:` section: enabled, relocalisation, vocabulary, every LoopConfig key at
// the top (global_ba, min_keyframes, detector: {...}, ransac: {...}, ...), RelocConfig under
// `reloc:`. Absent keys keep c's values; unknown keys are errors naming the file and line.
void read_loop_closing(const YAML::Node& node, LoopClosingConfig& c, const std::string& ctx);
SlamConfig load_slam_config(const std::string& path);

}  // namespace s3m::slam
