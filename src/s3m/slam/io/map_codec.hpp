#pragma once
// The Map's binary encoding inside slam_map.bin (map_io.hpp has the file around it). Internal to
// the slam module: MapIo is the Map's friend so a loaded map gets back its exact ids, culled chain
// and id counters, which trajectories and the pipeline's keyframe store refer to.
#include "s3m/core/byte_io.hpp"
#include "s3m/core/camera.hpp"
#include "s3m/slam/map/map.hpp"

namespace s3m::slam {

class MapIo {
 public:
  static void encode(const Map& map, ByteWriter& w);
  // Reads what encode wrote and checks its consistency (r.fail() on any violation). camera: the
  // map's own, for the keypoint grids. version: the file's (map_io.cpp lists what each one holds).
  static Map decode(ByteReader& r, const PinholeCamera& camera, std::uint32_t version);
  // A live or culled keyframe of map.
  static bool knows_keyframe(const Map& map, KeyframeId id) {
    return map.keyframes_.count(id) || map.culled_.count(id);
  }
};

}  // namespace s3m::slam
