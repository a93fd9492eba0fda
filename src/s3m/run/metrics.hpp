#pragma once
// metrics.json of a run: counts, timings per stage (mean/p50/p95 ms), trajectory error against
// ground truth (ATE/RPE), segmentation mIoU against ground-truth labels, map statistics and map
// mIoU against a ground-truth voxel map, whenever the dataset provides them.
#include <string>

#include <nlohmann/json.hpp>

#include "s3m/pipeline/frame_source.hpp"
#include "s3m/pipeline/outputs.hpp"
#include "s3m/pipeline/pipeline.hpp"

namespace s3m::run {

// A frame the run skipped because its files could not be read (RunInfo::skipped).
struct SkippedFrame {
  std::size_t index = 0;
  std::string error;  // the reader's message: file, problem, what was expected
};

struct RunInfo {
  std::string dataset_dir, config_file, poses, segmenter;
  std::string segmenter_reason;  // why this segmenter (pipeline::SegmenterChoice::reason)
  double wall_time_s = 0;
  bool interrupted = false;
  std::size_t frames_total = 0;
  std::string loaded_map;  // --map folder ("" = none)
  bool localize_only = false;
  std::string depth_registration;     // resolve_depth_registration(): what was decided and why
  std::vector<std::string> overlays;  // overlays the run's automatic decisions applied (config_overlays.hpp)
  double depth_median_m = 0;          // check_depth_scale() over the sample frames (0 = not checked)
  std::string depth_scale_warning;    // its warning ("" = plausible)
  std::vector<SkippedFrame> skipped;  // unreadable frames (dataset.max_unreadable_in_a_row)
  std::string stopped_by;             // why the run stopped before its last frame ("" = it did not)
};

// Files a dataset may carry for evaluation (s3m simulator output): ground-truth voxel map.
std::string find_gt_voxel_map(const std::string& dataset_dir);  // "" when absent

nlohmann::json compute_metrics(const pipeline::Pipeline& pipeline, const pipeline::FrameSource& source,
                               const pipeline::PipelineConfig& config, const RunInfo& info,
                               const pipeline::OutputPaths& paths);

// Side effect: with ground truth, evaluate_trajectory() writes the plot script's inputs
// (report/trajectory_aligned.txt, report/groundtruth.txt, report/rpe_series.txt).
// Writes metrics.json atomically.
// metrics.json's "outputs": where each output file is.
nlohmann::json outputs_json(const pipeline::OutputPaths& paths);
void write_metrics(const nlohmann::json& metrics, const pipeline::OutputPaths& paths);

}  // namespace s3m::run
