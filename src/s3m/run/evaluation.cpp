#include "s3m/run/evaluation.hpp"

#include <filesystem>

#include <Eigen/SVD>

#include <spdlog/spdlog.h>

#include "s3m/core/error.hpp"
#include "s3m/eval/report.hpp"
#include "s3m/eval/trajectory_eval.hpp"
#include "s3m/io/atomic_file.hpp"
#include "s3m/io/gt_voxels.hpp"

namespace s3m::run {
namespace fs = std::filesystem;
using nlohmann::json;

namespace {

eval::EvalOptions eval_options(const pipeline::PipelineConfig& config) {
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

TrajectoryScore evaluate_trajectory(const pipeline::Pipeline& p, const pipeline::FrameSource& source,
                                    const pipeline::PipelineConfig& config,
                                    const pipeline::OutputPaths& paths) {
  TrajectoryScore s;
  const io::Trajectory& gt = source.groundtruth();
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
  s.T_est_gt = align_poses(ev.poses.T_w_est, ev.poses.T_w_gt);
  const std::string report_dir = paths.out_dir + "/report";
  std::error_code ec;
  fs::create_directories(report_dir, ec);
  if (ec) throw Error("outputs: cannot create '" + report_dir + "': " + ec.message());
  io::write_text_atomic(report_dir + "/plot_data.json", eval::plot_data_json(gt, {est}, {ev}).dump());

  // The robot trajectory against the robot ground truth, when the dataset has it (simulator).
  const fs::path gt_robot = fs::path(source.eval_dir()) / "groundtruth_robot.txt";
  if (!source.eval_dir().empty() && fs::exists(gt_robot)) {
    try {
      const io::Trajectory est_r = pipeline::robot_trajectory(est, config.slam.T_c_r);
      s.json["robot"] = summary(
          eval::evaluate_trajectory(io::read_tum_trajectory(gt_robot.string()), est_r, options, "s3m robot"));
    } catch (const Error& e) {
      s.json["robot"] = {{"error", e.what()}};
    }
  }
  return s;
}

SE3 align_poses(const std::vector<SE3>& T_w_est, const std::vector<SE3>& T_w_gt) {
  require(!T_w_est.empty() && T_w_est.size() == T_w_gt.size(), "align_poses: need equally many (>0) poses");
  Mat3 M = Mat3::Zero();
  for (std::size_t i = 0; i < T_w_est.size(); ++i) M += T_w_est[i].linear() * T_w_gt[i].linear().transpose();
  const Eigen::JacobiSVD<Mat3> svd(M, Eigen::ComputeFullU | Eigen::ComputeFullV);
  Mat3 D = Mat3::Identity();
  D(2, 2) = (svd.matrixU() * svd.matrixV().transpose()).determinant() < 0 ? -1.0 : 1.0;
  const Mat3 R = svd.matrixU() * D * svd.matrixV().transpose();
  Vec3 t = Vec3::Zero();
  for (std::size_t i = 0; i < T_w_est.size(); ++i)
    t += T_w_est[i].translation() - R * T_w_gt[i].translation();
  return make_se3(R, t / static_cast<double>(T_w_est.size()));
}

MapScore score_map(const pipeline::MapIntegrator& map, const std::string& gt_path, const SE3& T_map_gt) {
  return score_map(map.tree(), gt_path, T_map_gt);
}

MapScore score_map(const mapping::SemanticOcTree& tree, const std::string& gt_path, const SE3& T_map_gt) {
  io::GtVoxelMap gt = io::read_gt_voxels(gt_path);
  const Eigen::Isometry3f T = T_map_gt.cast<float>();
  for (auto& c : gt.centres_w) c = T * c;
  MapScore s;
  s.gt_total = gt.centres_w.size();
  s.all = mapping::evaluate_map(tree, gt);
  io::GtVoxelMap seen;
  seen.resolution_m = gt.resolution_m;
  for (std::size_t i = 0; i < gt.centres_w.size(); ++i) {
    const Eigen::Vector3f& c = gt.centres_w[i];
    if (!tree.search(c.x(), c.y(), c.z())) continue;  // unknown space: no camera saw it
    seen.centres_w.push_back(c);
    seen.labels.push_back(gt.labels[i]);
  }
  s.gt_observed = seen.centres_w.size();
  if (s.gt_observed == 0) return s;
  s.observed = mapping::evaluate_map(tree, seen);
  for (ClassId c : seen.labels)
    if (c != cls::kUnknown) s.per_class_iou[c] = s.observed.iou.count(c) ? s.observed.iou.at(c) : 0.0;
  double sum = 0;
  for (const auto& [c, v] : s.per_class_iou) sum += v;
  s.miou = s.per_class_iou.empty() ? 0.0 : sum / s.per_class_iou.size();
  return s;
}

}  // namespace s3m::run
