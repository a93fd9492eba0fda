#pragma once
// `s3m merge RUN_A RUN_B --out OUT` as a library call: two saved sessions of the same
// place (each a folder `s3m run --out` wrote: slam_map.bin + kept_clouds.bin) become one. Place
// recognition finds where B's keyframes see A's map (slam::merge_sessions: BoW candidates,
// geometric verification, an alignment several pairs agree on), B's SLAM map is merged into A's
// world (SE3 from 3D-3D matches, point fusion, welding BA, essential graph over both), and the
// semantic map is rebuilt from both runs' kept clouds at their merged keyframe poses with the
// fusion policy of `config.map` (A's clouds first, then B's).
//
// OUT receives slam_map.bin and kept_clouds.bin (a session `s3m run --map OUT` continues in),
// map.ot and map.ply, keyframes.txt (every keyframe, A's world), trajectory_camera_a.txt and
// trajectory_camera_b.txt (each run's trajectory_camera.txt, when it has one, re-expressed in the
// merged world through its nearest keyframe in time) and merge.json (what was matched).
#include <map>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "s3m/io/trajectory.hpp"
#include "s3m/pipeline/pipeline_config.hpp"
#include "s3m/slam/loop/map_merge.hpp"

namespace s3m::run {

struct MergeRunsOptions {
  std::string run_a, run_b, out_dir;
  // map: resolution and fusion policy of the rebuilt semantic map; slam.loop_closing: vocabulary
  // and the verification thresholds.
  pipeline::PipelineConfig config;
  slam::SessionMergeConfig search;
};

// Throws s3m::Error / ParseError naming the file: a missing, foreign, corrupt or other-version
// file, maps of different cameras or vocabularies, runs that do not overlap (what was tried).
// Returns what merge.json holds.
nlohmann::json merge_runs(const MergeRunsOptions& options);

// The TUM trajectory in `path` with each pose moved as the keyframe nearest to it in time moved:
// correction_at maps keyframe stamps [s] to T_after * T_before^-1. Empty when correction_at is.
io::Trajectory corrected_trajectory(const std::string& path, const std::map<double, SE3>& correction_at);

// The names a merge owns in its output folder (for io::StagedFolder::commit): the session, the map,
// keyframes.txt, merge.json, unplaced/, and every trajectory_camera_<a|b|N>.txt already in out_dir
// (an earlier merge of more runs must not leave its extra trajectories behind).
std::vector<std::string> merge_output_names(const std::string& out_dir);

}  // namespace s3m::run
