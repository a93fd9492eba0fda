#pragma once
// `s3m merge RUN_1 RUN_2 ... RUN_N --out OUT` as a library call: N saved sessions of one building
// become one, merged in the order of their place-recognition overlap. Every pair of runs is
// searched as `s3m merge` searches two (slam::find_session_overlap: BoW candidates, geometric
// verification, an alignment enough verified pairs agree on); the pair with the most agreeing
// verified pairs starts the map (the one listed first of the two is the world), then the run with
// the strongest overlap with any run already merged joins next (a maximum spanning tree of the
// overlap graph, grown as Prim's algorithm does), each merged into everything merged before it
// (slam::merge_sessions). A run that overlaps none of the merged ones is not placed: it is
// reported and copied as it is into OUT/unplaced/<k>/, never dropped.
//
// OUT receives what `s3m merge A B` writes (slam_map.bin, kept_clouds.bin, map.ot, map.ply,
// keyframes.txt), trajectory_camera_<k>.txt per merged run (k: its 1-based position on the
// command line, re-expressed in the merged world) and merge.json: the merge order, which run
// joined through which by how many verified pairs, which were not placed, the overlap matrix.
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "s3m/pipeline/pipeline_config.hpp"
#include "s3m/slam/loop/map_merge.hpp"

namespace s3m::run {

struct MergeManyOptions {
  std::vector<std::string> runs;  // folders `s3m run --out` wrote (slam_map.bin, kept_clouds.bin)
  std::string out_dir;
  pipeline::PipelineConfig config;  // as MergeRunsOptions::config
  slam::SessionMergeConfig search;
};

// Throws s3m::Error naming the file or folder for fewer than two runs, a run listed twice, a
// missing or foreign session file, maps of different cameras or vocabularies, or an output folder
// that is one of the runs. Runs that overlap nothing are reported, not thrown. Returns merge.json.
nlohmann::json merge_many(const MergeManyOptions& options);

}  // namespace s3m::run
