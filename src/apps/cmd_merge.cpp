// `s3m merge RUN_A RUN_B [RUN_C ...] --out OUT`: saved sessions of one place merged into one (two:
// run::merge_runs; more: run::merge_many, in the order of their overlap).
#include <iostream>

#include "commands.hpp"
#include "s3m/core/error.hpp"
#include "s3m/run/merge_many.hpp"
#include "s3m/run/session_merge.hpp"

namespace s3m::apps {

namespace {

struct MergeArgs {
  std::vector<std::string> runs;
  std::string out, config, vocab;
  slam::SessionMergeConfig search;
};

void print_summary(const nlohmann::json& j, const std::string& out) {
  const auto& m = j["matched"];
  std::cout << "merged: RUN_B keyframe " << m["b_keyframe"] << " (frame " << m["b_frame_index"]
            << ") recognised at RUN_A keyframe " << m["a_keyframe"] << " (frame " << m["a_frame_index"]
            << "), " << m["projection_matches"] << " matches, " << m["agreeing_pairs"] << " of "
            << m["verified_pairs"] << " verified pairs agree\n"
            << "map: " << j["keyframes_a"] << " + " << j["keyframes_b"] << " keyframes, "
            << j["map"]["voxels"] << " occupied voxels\n"
            << "outputs: " << out << "\n";
}

void print_many(const nlohmann::json& j, const std::string& out) {
  for (const auto& r : j["runs"]) {
    std::cout << "run " << r["run"] << " (" << r["dir"].get<std::string>()
              << "): " << r["status"].get<std::string>();
    if (r["status"] == "joined")
      std::cout << " through run " << r["joined_to"] << ", " << r["agreeing_pairs"] << " of "
                << r["verified_pairs"] << " verified pairs agree";
    if (r["status"] == "not placed")
      std::cout << " (no verified overlap with the merged runs; kept as " << r["kept_as"].get<std::string>()
                << ")";
    std::cout << "\n";
  }
  std::cout << "merge order: " << j["order"].dump() << "; map: " << j["map"]["voxels"] << " occupied voxels\n"
            << "outputs: " << out << "\n";
}

}  // namespace

void register_merge(CLI::App& app) {
  auto args = std::make_shared<MergeArgs>();
  auto* cmd = app.add_subcommand(
      "merge",
      "Merge saved runs of the same place (s3m run --out folders) into one session: two, RUN_B into RUN_A's "
      "world; more, in the order of their place-recognition overlap, runs that overlap none kept apart");
  cmd->add_option(
         "runs", args->runs,
         "the runs (slam_map.bin, kept_clouds.bin; same camera and vocabulary). Two: the first's world is "
         "kept. More: the strongest-overlapping pair starts (its first-listed run is the world)")
      ->required()
      ->expected(2, -1);
  cmd->add_option("--out", args->out, "output folder (not one of the runs)")->required();
  cmd->add_option(
      "--config", args->config,
      "pipeline preset: the semantic map's resolution and fusion policy, place recognition thresholds "
      "(default: built-in defaults)");
  cmd->add_option("--vocab", args->vocab,
                  "bag-of-words vocabulary (default: the preset's, else vocab/orb_k10_l5.bin)");
  cmd->add_option("--candidates", args->search.candidates_per_keyframe,
                  "RUN_A keyframes verified per RUN_B keyframe, best BoW score first (default 3)");
  cmd->add_option("--min-agreeing", args->search.min_agreeing,
                  "verified keyframe pairs that must agree on the alignment (default 2)");
  cmd->callback([args] {
    pipeline::PipelineConfig config =
        args->config.empty() ? pipeline::PipelineConfig{} : pipeline::load_pipeline_config(args->config);
    if (!args->vocab.empty()) config.slam.loop_closing.vocabulary = args->vocab;
    if (args->runs.size() > 2) {
      run::MergeManyOptions o{args->runs, args->out, config, args->search};
      print_many(run::merge_many(o), args->out);
      return;
    }
    run::MergeRunsOptions o;
    o.run_a = args->runs.at(0);
    o.run_b = args->runs.at(1);
    o.out_dir = args->out;
    o.config = config;
    o.search = args->search;
    print_summary(run::merge_runs(o), args->out);
  });
}

}  // namespace s3m::apps
