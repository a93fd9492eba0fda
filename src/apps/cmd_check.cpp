// `s3m check DATASET [--config PRESET] [--camera FILE|PRESET]`: what s3m makes of a dataset folder
// before a run (layout, camera, timing, ground truth, depth registration and scale, segmenter).
#include <iostream>

#include "commands.hpp"
#include "s3m/pipeline/dataset_check.hpp"

namespace s3m::apps {

void register_check(CLI::App& app) {
  struct Args {
    std::string dataset, config, camera;
  };
  auto args = std::make_shared<Args>();
  auto* cmd = app.add_subcommand("check", "Say what s3m makes of a dataset folder before a run: layout, camera, "
                                          "timing, ground truth, depth registration and scale, segmenter");
  cmd->add_option("dataset", args->dataset, "dataset folder (TUM layout, ETH3D, 7-Scenes, ScanNet, Replica)")->required();
  cmd->add_option("--config", args->config, "pipeline preset the run would use (its dataset and segmenter sections)");
  cmd->add_option("--camera", args->camera, "camera file or preset instead of the dataset's (dataset.camera)");
  cmd->callback([args] {
    pipeline::PipelineConfig config =
        args->config.empty() ? pipeline::PipelineConfig{} : pipeline::load_pipeline_config(args->config);
    if (!args->camera.empty()) config.dataset.camera = args->camera;
    std::cout << pipeline::format_dataset_check(pipeline::check_dataset(args->dataset, config));
  });
}

}  // namespace s3m::apps
