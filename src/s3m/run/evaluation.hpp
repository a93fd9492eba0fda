#pragma once
// Evaluation of a run against the dataset's ground truth: trajectory (ATE/RPE through s3m::eval)
// and semantic map (mIoU against the simulator's ground-truth voxel map).
#include <map>
#include <optional>
#include <string>

#include <nlohmann/json.hpp>

#include "s3m/eval/align.hpp"
#include "s3m/mapping/metrics.hpp"
#include "s3m/pipeline/frame_source.hpp"
#include "s3m/pipeline/outputs.hpp"
#include "s3m/pipeline/pipeline.hpp"

namespace s3m::run {

struct TrajectoryScore {
  nlohmann::json json = nlohmann::json::object();  // {} without ground truth
  // The ground-truth world in the estimate's (= the map's) frame, from whole poses (see below).
  std::optional<SE3> T_est_gt;
};

// Rigid transform T_est_gt minimising the chordal distance of all matched poses:
// R = argmin sum |R_est_i - R R_gt_i|_F (SVD of sum R_est_i R_gt_i^T), t = mean(p_est_i - R p_gt_i).
// Unlike ATE's position-only alignment, it is well-posed for short or straight flights, where
// positions alone leave the rotation about the path undetermined (and a map would be misplaced).
SE3 align_poses(const std::vector<SE3>& T_w_est, const std::vector<SE3>& T_w_gt);

// ATE/RPE of the camera trajectory (and of the robot trajectory when the dataset has
// groundtruth_robot.txt). Writes report/plot_data.json for tools/plot_trajectories.py.
TrajectoryScore evaluate_trajectory(const pipeline::Pipeline& pipeline, const pipeline::FrameSource& source,
                                    const pipeline::PipelineConfig& config,
                                    const pipeline::OutputPaths& paths);

struct MapScore {
  mapping::MapEvaluation observed;  // over ground-truth voxels in space the map observed
  mapping::MapEvaluation all;       // over every ground-truth voxel (recall = coverage of the scene)
  std::size_t gt_observed = 0, gt_total = 0;
  // Mean IoU over the classes present in the observed ground truth: the same definition as the
  // per-frame segmentation mIoU (classes with ground-truth pixels), so the two compare directly.
  // mapping::evaluate_map's own mIoU also averages in classes only predicted (IoU 0 each).
  double miou = 0;
  std::map<ClassId, double> per_class_iou;
};
// mapping::evaluate_map against the ground-truth voxel map, its centres moved into the map's frame
// with T_map_gt. A short flight sees part of a room: classes it never saw would score IoU 0 and make
// the map look worse than the frames it was built from, so the headline numbers (`observed`) use only
// ground-truth voxels whose cell the map knows (free or occupied, i.e. inside some camera's view).
MapScore score_map(const pipeline::MapIntegrator& map, const std::string& gt_voxel_map_path,
                   const SE3& T_map_gt);
MapScore score_map(const mapping::SemanticOcTree& tree, const std::string& gt_voxel_map_path,
                   const SE3& T_map_gt);

}  // namespace s3m::run
