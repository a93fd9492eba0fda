#pragma once
// Evaluation of a run against the dataset's ground truth: trajectory (ATE/RPE through s3m::eval)
// and semantic map (mIoU against the simulator's ground-truth voxel map).
#include <map>
#include <optional>
#include <string>

#include <nlohmann/json.hpp>

#include "s3m/eval/align.hpp"
#include "s3m/io/tum_dataset.hpp"
#include "s3m/pipeline/outputs.hpp"
#include "s3m/pipeline/pipeline.hpp"

namespace s3m::pipeline {

struct TrajectoryScore {
  nlohmann::json json = nlohmann::json::object();  // {} without ground truth
  std::optional<eval::Sim3> alignment;              // estimate world -> ground-truth world
};

// ATE/RPE of the camera trajectory (and of the robot trajectory when the dataset has
// groundtruth_robot.txt). Writes report/plot_data.json for tools/plot_trajectories.py.
TrajectoryScore evaluate_trajectory(const Pipeline& pipeline, const io::TumDataset& dataset,
                                    const PipelineConfig& config, const OutputPaths& paths);

struct MapScore {
  double miou = 0;
  std::map<ClassId, double> per_class_iou;
  std::size_t gt_observed = 0, gt_total = 0;  // ground-truth voxels the map has as occupied / all of them
};
// Every ground-truth voxel is looked up in the map (its centre moved into the map's frame with
// T_map_gt); occupied ones compare the map's most probable label with the true class. Ground-truth
// voxels the map never observed do not enter the IoU; their share is reported as coverage.
MapScore score_map(const MapIntegrator& map, const std::string& gt_voxel_map_path, const SE3& T_map_gt);

}  // namespace s3m::pipeline
