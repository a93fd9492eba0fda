#pragma once
// All SLAM settings in one plain struct with defaults; loadable from YAML (config/slam_*.yaml).
#include <string>

#include <yaml-cpp/yaml.h>

#include "s3m/core/se3.hpp"
#include "s3m/features/frame_features.hpp"
#include "s3m/slam/local_mapper.hpp"
#include "s3m/slam/tracker.hpp"

namespace s3m::slam {

struct SlamConfig {
  features::FeatureConfig features;
  TrackerConfig tracker;
  MapperConfig mapper;
  SE3 T_c_r = SE3::Identity();  // robot (body) frame to camera frame: T_w_r = T_w_c * T_c_r
  bool threaded = false;        // tracking and local mapping in separate threads
  int queue_capacity = 4;       // bounded queues between the two

  void validate() const;
};

// Reads a SlamConfig from a YAML node (sections: features/orb, tracker, mapper/ba, calibration,
// threaded). Absent keys keep their defaults; unknown keys are errors naming the file and line.
// T_c_r is given as `T_c_r: {t: [x, y, z], q: [qx, qy, qz, qw]}` (metres, unit quaternion).
SlamConfig slam_config_from_yaml(const YAML::Node& node, const std::string& ctx);
SlamConfig load_slam_config(const std::string& path);

}  // namespace s3m::slam
