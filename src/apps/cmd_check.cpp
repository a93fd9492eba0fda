// `s3m check DATASET|REC|--rosbag FILE [--config PRESET] [--camera FILE|PRESET] [--all-settings]`: what
// s3m makes of a dataset folder or a bag before a run (layout or recorder, camera, timing, ground
// truth, depth registration and scale, segmenter, the settings a run would use).
#include <iostream>

#include "commands.hpp"
#include "ros_support.hpp"
#include "s3m/core/error.hpp"
#include "s3m/pipeline/factories.hpp"
#include "s3m/run/dataset_check.hpp"

namespace s3m::apps {

void register_check(CLI::App& app) {
  struct Args {
    std::string dataset, config, camera;
    bool all_settings = false;
    RosbagArgs bag;
  };
  auto args = std::make_shared<Args>();
  auto* cmd = app.add_subcommand("check",
                                 "Say what s3m makes of a dataset folder or a rosbag before a run: layout "
                                 "or recorder, camera, timing, ground truth, depth registration and scale, "
                                 "segmenter, settings");
  cmd->add_option(
      "dataset", args->dataset,
      "dataset folder (TUM layout, ETH3D, 7-Scenes, ScanNet, Replica) or ROS 2 recording (.mcap, .db3, "
      "rosbag2 folder)");
  cmd->add_option("--config", args->config,
                  "pipeline preset the run would use (its dataset and segmenter sections)");
  cmd->add_option("--camera", args->camera,
                  "camera file or preset instead of the dataset's (dataset.camera)");
  cmd->add_flag(
      "--all-settings", args->all_settings,
      "print every setting a run would use (config_effective.yaml), not only those that differ from "
      "the defaults");
  add_rosbag_options(*cmd, args->bag);
  cmd->callback([args] {
    if (args->bag.bag.empty() == args->dataset.empty())
      throw Error("check: give either a dataset directory or --rosbag FILE.bag (exactly one)");
    pipeline::PipelineConfig config =
        args->config.empty() ? pipeline::PipelineConfig{} : pipeline::load_pipeline_config(args->config);
    if (!args->camera.empty()) {
      config.dataset.camera = args->camera;
      pipeline::mark_written(config, "dataset.camera");
    }
    if (is_ros2_recording(args->dataset)) {
      const auto source = ros2_source(args->dataset, args->bag, config, !args->config.empty())(config);
      std::cout << run::format_dataset_check(
          run::check_frame_source(*source, config, pipeline::simulator_sign("", source->has_labels())),
          args->all_settings);
      return;
    }
    if (!args->dataset.empty()) {
      std::cout << run::format_dataset_check(run::check_dataset(args->dataset, config), args->all_settings);
      return;
    }
    const auto source = rosbag_source(args->bag)(config);
    std::cout << run::format_dataset_check(
        run::check_frame_source(*source, config, pipeline::simulator_sign("", source->has_labels())),
        args->all_settings);
  });
}

}  // namespace s3m::apps
