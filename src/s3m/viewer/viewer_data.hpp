#pragma once
// The map as the browser viewer (tools/viewer/viewer.js) reads it: one JSON object with the class
// list, trajectory, keyframes and object instances, and the occupied voxels packed into a binary
// buffer (base64) instead of one JSON object per voxel, so a 200,000-voxel map stays a few MB and
// decodes in tens of milliseconds (docs/RESULTS.md, viewer load time).
//
// Voxel buffer, little endian, structure of arrays for N voxels with k label slots each:
//   uint16 kx[N], ky[N], kz[N]   OctoMap keys at the finest depth: centre = (key - key_offset + 0.5) * res
//   uint16 label[N*k]            top-k class ids, voxel-major, most probable first (0 = empty slot)
//   uint8  prob[N*k]             their probabilities * 255, rounded
//   uint8  rgb[N*3]              observed colour (200,200,200 when none was observed)
//   uint8  occupancy[N]          occupancy probability * 255, rounded
// Pruned occupied nodes are expanded into their finest voxels, so N equals metrics.json's
// map.voxels for the same map. The buffer's layout is described in the JSON ("layout").
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "s3m/core/camera.hpp"
#include "s3m/io/trajectory.hpp"
#include "s3m/mapping/semantic_octree.hpp"

namespace s3m::viewer {

struct VoxelBuffer {
  std::size_t count = 0;
  int k = 0;
  std::vector<std::uint8_t> bytes;
};

// Occupied finest voxels of the map, in the tree's leaf order (deterministic).
VoxelBuffer encode_voxels(const mapping::SemanticOcTree& map);

std::string base64_encode(const std::vector<std::uint8_t>& bytes);

// What the viewer shows besides the voxels. Trajectories are T_w_c in the map's world frame.
struct SceneExtras {
  io::Trajectory trajectory;       // may be empty
  io::Trajectory keyframes;        // drawn as small frusta; may be empty
  std::optional<PinholeCamera> camera;  // frustum shape (default 4:3, 60 degrees wide)
  std::size_t instance_min_voxels = 10;  // smaller object instances are not listed
  std::string title;
};

// The whole scene as the JSON object viewer.js expects (window.S3M_VIEWER_DATA), voxels included.
nlohmann::json scene_json(const mapping::SemanticOcTree& map, const SceneExtras& extras);

}  // namespace s3m::viewer
