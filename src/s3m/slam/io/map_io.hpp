#pragma once
// SLAM map persistence (`slam_map.bin`): a map that outlives the run that built it.
// The file holds every keyframe (id, source frame, time, pose T_w_c, keypoints, descriptors, depth
// and virtual right coordinate per keypoint, the map point seen at each keypoint, BoW vector and
// direct index), every map point (position, descriptor, viewing direction, distance range,
// observations, reference keyframe, tracking statistics), the covisibility graph, the spanning
// tree, the loop edges (tree + loop edges + strong covisibility = the essential graph), the
// culled-keyframe chain (so poses stored against a culled keyframe still resolve), the id
// counters, the camera and the vocabulary's checksum.
//
// Format, version 2, host byte order (little-endian):
//   "S3MSLAM\0" | u32 version | u64 payload bytes | payload | u64 FNV-1a(payload) | "S3MSLEND"
// Written atomically (temporary file + fsync + rename). Saving what was loaded gives the same
// bytes. Loading checks, in order: the file exists, magic, version, size, checksum, the map's
// internal consistency (both sides of every observation, graph edges, id counters), then camera
// and vocabulary against the session's; every failure is an s3m::ParseError naming the file and
// what did not match. Derived structures (keypoint grids, the BoW inverted index) are rebuilt.
#include <cstdint>
#include <string>
#include <utility>
#include <vector>

#include "s3m/core/camera.hpp"
#include "s3m/slam/loop/loop_keyframe_index.hpp"
#include "s3m/slam/map/map.hpp"

namespace s3m::slam {

using LoopEdges =
    std::vector<std::pair<KeyframeId, KeyframeId>>;  // (current, loop) keyframes of closed loops

// A map read back from a file, with the BoW index over its keyframes.
struct LoadedSlamMap {
  Map map;
  KeyFrameBowIndex index;
  LoopEdges loop_edges;
  PinholeCamera camera;  // the camera the map was built with (equal to the session's)
};

// The file's bytes (what save_slam_map writes). index must cover every keyframe of map.
std::string serialise_slam_map(const Map& map, const KeyFrameBowIndex& index, const LoopEdges& loop_edges,
                               const PinholeCamera& camera);
void save_slam_map(const std::string& path, const Map& map, const KeyFrameBowIndex& index,
                   const LoopEdges& loop_edges, const PinholeCamera& camera);

// Loads path for a session with this camera and vocabulary (direct_level: the BoW direct index
// level the session matches with; the stored index is reused when it was made at that level).
// Throws ParseError: missing/unreadable, not a SLAM map, other version, truncated, corrupt
// (checksum), inconsistent, made with another camera or another vocabulary.
LoadedSlamMap load_slam_map(const std::string& path, const PinholeCamera& camera,
                            std::shared_ptr<const features::Vocabulary> vocabulary, int direct_level = 2);
// The same with the map's own camera (no session to compare with: `s3m merge` loads the first run's
// map this way and the second with the first's camera).
LoadedSlamMap load_slam_map(const std::string& path, std::shared_ptr<const features::Vocabulary> vocabulary,
                            int direct_level = 2);

}  // namespace s3m::slam
