#pragma once
// A run's session in OUT, for a later run to continue in (`s3m run ... --map OUT/`):
//   slam_map.bin     the SLAM map (slam/map_io.hpp)
//   kept_clouds.bin  the labelled clouds the semantic map is built from, each anchored to a
//                    keyframe of that map, with every keyframe pose the store knows. The semantic
//                    map is rebuilt from them (not read from map.ot), so a later run that moves
//                    the loaded keyframes (loop closure, BA) re-integrates the old clouds too.
// kept_clouds.bin, version 1 (core/byte_io.hpp frame): u32 keyframes x {i64 id, pose T_w_kf},
// u32 clouds x {i64 keyframe, pose T_kf_c, i32 frame index, 3 f32 origin, u32 n, n x 3 f32 point
// (origin and points in the camera frame), u8 has colour, (3 n B colour), i32 k, n k x u16 label, n k x f32 probability}.
#include <string>

#include "s3m/pipeline/keyframe_store.hpp"

namespace s3m::pipeline {

inline constexpr const char* kSlamMapFile = "slam_map.bin";
inline constexpr const char* kKeptCloudsFile = "kept_clouds.bin";

// Atomic write.
void save_kept_clouds(const std::string& path, const KeyframeStore& store);
// Into an empty store (its budget applies). ParseError naming path: missing, not this format,
// other version, truncated, corrupt, inconsistent (a cloud anchored to an unknown keyframe).
void load_kept_clouds(const std::string& path, KeyframeStore& store);

}  // namespace s3m::pipeline
