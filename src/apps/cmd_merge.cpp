// `s3m merge RUN_A RUN_B --out OUT`: two saved sessions of one place merged into one.
#include <iostream>

#include "commands.hpp"
#include "s3m/core/error.hpp"
#include "s3m/run/session_merge.hpp"

namespace s3m::apps {

namespace {

struct MergeArgs {
  std::string run_a, run_b, out, config, vocab;
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

}  // namespace

void register_merge(CLI::App& app) {
  auto args = std::make_shared<MergeArgs>();
  auto* cmd = app.add_subcommand(
      "merge", "Merge two saved runs of the same place (s3m run --out folders) into one session");
  cmd->add_option("run_a", args->run_a,
                  "the run whose world the merged session keeps (slam_map.bin, kept_clouds.bin)")
      ->required();
  cmd->add_option("run_b", args->run_b, "the run merged into it (same camera and vocabulary)")->required();
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
    run::MergeRunsOptions o;
    o.run_a = args->run_a;
    o.run_b = args->run_b;
    o.out_dir = args->out;
    o.config =
        args->config.empty() ? pipeline::PipelineConfig{} : pipeline::load_pipeline_config(args->config);
    if (!args->vocab.empty()) o.config.slam.loop_closing.vocabulary = args->vocab;
    o.search = args->search;
    print_summary(run::merge_runs(o), args->out);
  });
}

}  // namespace s3m::apps
