#pragma once
// Evaluation of a run against the dataset's ground truth: trajectory (ATE/RPE through s3m::eval)
// and semantic map (mIoU against a ground-truth voxel map through s3m::mapping).
#include <map>
#include <string>

#include <nlohmann/json.hpp>

#include "s3m/io/tum_dataset.hpp"
#include "s3m/pipeline/outputs.hpp"
#include "s3m/pipeline/pipeline.hpp"

namespace s3m::pipeline {

// {} without ground truth; else ATE/RPE numbers. Writes report/trajectory_aligned.txt,
// report/groundtruth.txt and report/rpe_series.txt for the plots.
nlohmann::json evaluate_trajectory(const Pipeline& pipeline, const io::TumDataset& dataset,
                                   const PipelineConfig& config, const OutputPaths& paths);

struct MapScore {
  double miou = 0;
  std::map<ClassId, double> per_class_iou;
  std::size_t gt_observed = 0, gt_total = 0;  // ground-truth voxels the map has / all of them
};
MapScore score_map(const MapIntegrator& map, const std::string& gt_voxel_map_path);

}  // namespace s3m::pipeline
