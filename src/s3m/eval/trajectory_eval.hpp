#pragma once
// Trajectory accuracy as defined by the TUM RGB-D benchmark (Sturm et al., IROS 2012):
//  ATE: after aligning the estimate to ground truth, |p_gt_i - S p_est_i| per matched pose.
//  RPE: for pose pairs (i, j) a fixed delta apart, E = (Q_i^-1 Q_j)^-1 (P_i^-1 P_j) with Q = ground
//       truth and P = estimate (translations scaled by the Sim3 scale); trans = |t(E)| [m],
//       rot = angle(R(E)) [deg]. This is the paper's formula (also evo's); TUM's evaluate_rpe.py script
//       computes (P_i^-1 P_j)(Q_i^-1 Q_j)^-1, whose rotation angle is identical and whose translation
//       differs only by rotating the error with the pair's rotation error (see docs/RESULTS.md).
#include <string>
#include <vector>

#include "s3m/eval/align.hpp"
#include "s3m/io/trajectory.hpp"

namespace s3m::eval {

struct ErrorStats {
  double rmse = 0, mean = 0, median = 0, std = 0, min = 0, max = 0;  // std: population (numpy's default)
  std::size_t count = 0;
};
ErrorStats error_stats(std::vector<double> errors);  // all zeros for an empty input

// Pairs of ground-truth and estimated poses at associated timestamps (TUM associate.py rules).
struct MatchedPoses {
  std::vector<double> t_s;  // estimate timestamps
  std::vector<SE3> T_w_gt;  // ground truth pose
  std::vector<SE3> T_w_est; // estimated pose (estimate's own world frame)
};
MatchedPoses match_poses(const io::Trajectory& gt, const io::Trajectory& est, double max_dt_s = 0.02,
                         double offset_s = 0.0);

struct AteResult {
  ErrorStats stats_m;
  Sim3 alignment;             // maps the estimate's world into the ground truth's
  std::vector<double> errors_m;  // per matched pose
};
AteResult compute_ate(const MatchedPoses& matched, AlignMode mode);

enum class DeltaUnit { kSeconds, kFrames };
DeltaUnit parse_delta_unit(const std::string& name);  // "s" | "f"

struct RpeOptions {
  double delta = 1.0;  // seconds, or an integer number of matched frames
  DeltaUnit unit = DeltaUnit::kSeconds;
  void validate() const;
};

struct RpeResult {
  ErrorStats trans_m, rot_deg;
  std::vector<double> t_s;  // start time of each pair
  std::vector<double> trans_errors_m, rot_errors_deg;
};
// Pairs (i, j): frames: j = i + delta; seconds: j = the matched pose closest in time to t_i + delta,
// skipped when j <= i or t_i + delta lies beyond the last pose by more than half the median frame gap.
// scale multiplies the estimate's relative translations (the Sim3 scale; 1 for se3/none).
RpeResult compute_rpe(const MatchedPoses& matched, const RpeOptions& options, double scale = 1.0);

struct EvalOptions {
  double max_dt_s = 0.02;  // association window [s], TUM's default
  double offset_s = 0.0;   // added to estimate timestamps before association
  AlignMode align = AlignMode::kSe3;
  RpeOptions rpe;
  void validate() const;
};

struct TrajectoryEvaluation {
  std::string name;
  std::size_t matched = 0, gt_poses = 0, est_poses = 0;
  AteResult ate;
  RpeResult rpe;
  MatchedPoses poses;
};

// 1. associate, 2. align, 3. ATE, 4. RPE. Throws s3m::Error when fewer than 3 poses match
// (with the timestamp ranges of both trajectories, the usual cause being a different time base).
TrajectoryEvaluation evaluate_trajectory(const io::Trajectory& gt, const io::Trajectory& est,
                                         const EvalOptions& options = {}, const std::string& name = "estimate");

}  // namespace s3m::eval
