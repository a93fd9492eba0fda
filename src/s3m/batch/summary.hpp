#pragma once
// The merge stage of a batch (`s3m batch MANIFEST --out DIR --merge-stage`, the job after the
// runs): the runs that succeeded merged N-way (run::merge_many) into DIR/merged/, unless
// DIR/merged/ already holds the merge of exactly those runs; then DIR/summary.json and
// DIR/summary.html: per recording its status (with its error when it failed), frames, ATE where
// the dataset has ground truth, map size and mIoU; the merge: which runs joined, through which run
// and by how many verified pairs, which were not placed; the merged map's size, its mIoU and its
// coverage of the union of the runs' observed ground-truth voxels (simulator ground truth).
#include <optional>
#include <set>
#include <string>

#include <nlohmann/json.hpp>

#include "s3m/core/se3.hpp"

namespace s3m::batch {

nlohmann::json merge_stage(const std::string& manifest, const std::string& dir);

// The ground-truth world in a run's world: whole-pose alignment (run::align_poses) of the run's
// trajectory_camera.txt to its dataset's groundtruth.txt, poses paired within 1 ms. nullopt
// without ground truth or matching poses.
std::optional<SE3> T_run_gt(const std::string& run_dir, const std::string& dataset_dir);

// The ground-truth voxels (indices into the gt_voxels.txt file) whose cell a map knows (free or
// occupied: some camera saw it), the map at T_map_gt from the ground truth.
std::set<std::size_t> observed_gt_voxels(const std::string& map_ot, const std::string& gt_voxels,
                                         const SE3& T_map_gt);

// How many of a subset of the ground-truth voxels the map knows a cell within one voxel of (per
// axis: the map metrics' tolerance): its coverage of what other maps observed, apart from where
// each map's alignment puts the edge of the observed space.
std::size_t known_near(const std::string& map_ot, const std::string& gt_voxels, const SE3& T_map_gt,
                       const std::set<std::size_t>& subset);

// mIoU (run::score_map's definition: over the ground-truth classes present) of a map on a subset
// of the ground-truth voxels.
double miou_on(const std::string& map_ot, const std::string& gt_voxels, const SE3& T_map_gt,
               const std::set<std::size_t>& subset);

// summary.html from summary.json's content.
std::string summary_html(const nlohmann::json& summary);

}  // namespace s3m::batch
