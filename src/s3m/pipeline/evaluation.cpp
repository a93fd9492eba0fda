#include "s3m/pipeline/evaluation.hpp"

#include <filesystem>

#include <spdlog/spdlog.h>

#include "s3m/core/error.hpp"
#include "s3m/eval/report.hpp"
#include "s3m/eval/trajectory_eval.hpp"
#include "s3m/io/atomic_file.hpp"
#include "s3m/io/gt_voxels.hpp"
#include "s3m/semantics/seg_metrics.hpp"

namespace s3m::pipeline {
namespace fs = std::filesystem;
using nlohmann::json;

namespace {

eval::EvalOptions eval_options(const PipelineConfig& config) {
  eval::EvalOptions o;
  o.max_dt_s = config.eval.gt_max_dt_s;
  o.align = eval::parse_align_mode(config.eval.align);
  o.rpe.delta = config.eval.rpe_delta_s;
  o.rpe.unit = eval::DeltaUnit::kSeconds;
  return o;
}

// The headline numbers flat (what people grep for), eval's full record under "details".
json summary(const eval::TrajectoryEvaluation& ev) {
  return {{"ate_rmse_m", ev.ate.stats_m.rmse},
          {"rpe_trans_rmse_m", ev.rpe.trans_m.rmse},
          {"rpe_rot_rmse_deg", ev.rpe.rot_deg.rmse},
          {"matched", ev.matched},
          {"details", eval::to_json(ev)}};
}

}  // namespace

TrajectoryScore evaluate_trajectory(const Pipeline& p, const io::TumDataset& dataset, const PipelineConfig& config,
                                    const OutputPaths& paths) {
  TrajectoryScore s;
  const io::Trajectory& gt = dataset.groundtruth();
  if (gt.empty()) return s;
  const io::Trajectory est = p.poses().camera_trajectory();
  const eval::EvalOptions options = eval_options(config);
  eval::TrajectoryEvaluation ev;
  try {
    ev = eval::evaluate_trajectory(gt, est, options, "s3m camera");
  } catch (const Error& e) {  // e.g. fewer than 3 tracked frames: a result, not a crash
    s.json = {{"error", e.what()}};
    return s;
  }
  s.json = summary(ev);
  s.alignment = ev.ate.alignment;
  const std::string report_dir = paths.out_dir + "/report";
  fs::create_directories(report_dir);
  io::write_text_atomic(report_dir + "/plot_data.json", eval::plot_data_json(gt, {est}, {ev}).dump());

  // The robot trajectory against the robot ground truth, when the dataset has it (simulator).
  const fs::path gt_robot = fs::path(dataset.dir()) / "groundtruth_robot.txt";
  if (fs::exists(gt_robot)) {
    try {
      const io::Trajectory est_r = robot_trajectory(est, config.slam.T_c_r);
      s.json["robot"] = summary(eval::evaluate_trajectory(io::read_tum_trajectory(gt_robot.string()), est_r,
                                                          options, "s3m robot"));
    } catch (const Error& e) {
      s.json["robot"] = {{"error", e.what()}};
    }
  }
  return s;
}

MapScore score_map(const MapIntegrator& map, const std::string& gt_path, const SE3& T_map_gt) {
  const io::GtVoxelMap gt = io::read_gt_voxels(gt_path);
  const mapping::SemanticOcTree& tree = map.tree();
  MapScore s;
  s.gt_total = gt.centres_w.size();
  std::vector<ClassId> truth, pred;
  for (std::size_t i = 0; i < gt.centres_w.size(); ++i) {
    if (gt.labels[i] == cls::kUnknown) continue;
    const Vec3 p = T_map_gt * gt.centres_w[i].cast<double>();
    const auto* node = tree.search(p.x(), p.y(), p.z());
    if (!node || !tree.isNodeOccupied(node) || node->labels().empty()) continue;
    truth.push_back(gt.labels[i]);
    pred.push_back(node->labels().top());
  }
  s.gt_observed = truth.size();
  if (truth.empty()) return s;
  semantics::ConfusionMatrix cm(cls::kCount);
  cm.add(cv::Mat(1, static_cast<int>(truth.size()), CV_16UC1, truth.data()),
         cv::Mat(1, static_cast<int>(pred.size()), CV_16UC1, pred.data()));
  const semantics::SegMetrics m = cm.metrics();
  s.miou = m.miou;
  for (ClassId c : m.evaluated) s.per_class_iou[c] = m.iou[c];
  return s;
}

}  // namespace s3m::pipeline
