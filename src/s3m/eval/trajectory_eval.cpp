#include "s3m/eval/trajectory_eval.hpp"

#include <algorithm>
#include <cmath>
#include <numeric>

#include <fmt/format.h>

#include "s3m/core/error.hpp"
#include "s3m/io/association.hpp"

namespace s3m::eval {

ErrorStats error_stats(std::vector<double> e) {
  ErrorStats s;
  s.count = e.size();
  if (e.empty()) return s;
  const double n = static_cast<double>(e.size());
  double sum = 0, sum_sq = 0;
  for (double x : e) sum += x, sum_sq += x * x;
  s.mean = sum / n;
  s.rmse = std::sqrt(sum_sq / n);
  double var = 0;
  for (double x : e) var += (x - s.mean) * (x - s.mean);
  s.std = std::sqrt(var / n);
  std::sort(e.begin(), e.end());
  s.min = e.front();
  s.max = e.back();
  const std::size_t m = e.size() / 2;
  s.median = e.size() % 2 ? e[m] : 0.5 * (e[m - 1] + e[m]);
  return s;
}

MatchedPoses match_poses(const io::Trajectory& gt, const io::Trajectory& est, double max_dt_s, double offset_s) {
  MatchedPoses m;
  for (const auto& match : io::associate(io::timestamps(est), io::timestamps(gt), max_dt_s, -offset_s)) {
    m.t_s.push_back(est[match.a].t_s);
    m.T_w_est.push_back(est[match.a].T_w_x);
    m.T_w_gt.push_back(gt[match.b].T_w_x);
  }
  return m;
}

AteResult compute_ate(const MatchedPoses& matched, AlignMode mode) {
  std::vector<Vec3> p_est, p_gt;
  for (std::size_t i = 0; i < matched.t_s.size(); ++i) {
    p_est.push_back(matched.T_w_est[i].translation());
    p_gt.push_back(matched.T_w_gt[i].translation());
  }
  AteResult r;
  r.alignment = align_positions(p_est, p_gt, mode);
  for (std::size_t i = 0; i < p_est.size(); ++i) r.errors_m.push_back((p_gt[i] - r.alignment.apply(p_est[i])).norm());
  r.stats_m = error_stats(r.errors_m);
  return r;
}

DeltaUnit parse_delta_unit(const std::string& name) {
  if (name == "s") return DeltaUnit::kSeconds;
  if (name == "f") return DeltaUnit::kFrames;
  throw Error("unknown delta unit '" + name + "' (expected s for seconds or f for frames)");
}

void RpeOptions::validate() const {
  require(std::isfinite(delta) && delta > 0, "rpe: delta must be > 0");
  require(unit == DeltaUnit::kSeconds || delta == std::floor(delta), "rpe: a delta in frames must be an integer");
}

namespace {

std::vector<std::pair<std::size_t, std::size_t>> rpe_pairs(const std::vector<double>& t, const RpeOptions& opt) {
  std::vector<std::pair<std::size_t, std::size_t>> pairs;
  const std::size_t n = t.size();
  if (opt.unit == DeltaUnit::kFrames) {
    const auto d = static_cast<std::size_t>(opt.delta);
    for (std::size_t i = 0; i + d < n; ++i) pairs.emplace_back(i, i + d);
    return pairs;
  }
  std::vector<double> gaps;
  for (std::size_t i = 1; i < n; ++i) gaps.push_back(t[i] - t[i - 1]);
  std::nth_element(gaps.begin(), gaps.begin() + static_cast<long>(gaps.size() / 2), gaps.end());
  const double half_gap = gaps.empty() ? 0.0 : 0.5 * gaps[gaps.size() / 2];
  for (std::size_t i = 0; i < n; ++i) {
    const double target = t[i] + opt.delta;
    if (target > t.back() + half_gap) break;  // past the end: no pose that far ahead
    const std::size_t j = io::closest_index(t, target);
    if (j > i) pairs.emplace_back(i, j);
  }
  return pairs;
}

}  // namespace

RpeResult compute_rpe(const MatchedPoses& m, const RpeOptions& options, double scale) {
  options.validate();
  RpeResult r;
  for (const auto& [i, j] : rpe_pairs(m.t_s, options)) {
    const SE3 dQ = m.T_w_gt[i].inverse() * m.T_w_gt[j];
    SE3 dP = m.T_w_est[i].inverse() * m.T_w_est[j];
    dP.translation() *= scale;
    const SE3 E = dQ.inverse() * dP;
    r.t_s.push_back(m.t_s[i]);
    r.trans_errors_m.push_back(E.translation().norm());
    r.rot_errors_deg.push_back(rotation_angle_rad(E.linear()) * 180.0 / M_PI);
  }
  r.trans_m = error_stats(r.trans_errors_m);
  r.rot_deg = error_stats(r.rot_errors_deg);
  return r;
}

void EvalOptions::validate() const {
  require(std::isfinite(max_dt_s) && max_dt_s > 0, "eval: max_dt_s must be > 0");
  require(std::isfinite(offset_s), "eval: offset_s must be finite");
  rpe.validate();
}

namespace {

// What the timestamps say about a failed association, when they say something: one side in
// nanoseconds (ROS and EuRoC tools write them; TUM files use seconds: its span is ~1e9 times the
// other's), or two clocks that cover similar durations but do not overlap (a recording's clock
// against a ground truth that starts at 0).
std::string association_hint(const io::Trajectory& gt, const io::Trajectory& est, double offset_s) {
  const double g0 = gt.front().t_s, g1 = gt.back().t_s, e0 = est.front().t_s + offset_s, e1 = est.back().t_s + offset_s;
  const double dg = g1 - g0, de = e1 - e0;
  if (dg <= 0 || de <= 0) return "";
  const auto about_1e9 = [](double ratio) { return ratio > 1e8 && ratio < 1e10; };
  if (about_1e9(de / dg) || about_1e9(dg / de))
    return fmt::format(": the {} timestamps look like nanoseconds (its span is {:.3g} times the other's); "
                       "convert them to seconds", de > dg ? "estimate's" : "ground truth's", std::max(de / dg, dg / de));
  if ((e0 > g1 || e1 < g0) && de > 0.5 * dg && de < 2 * dg)
    return fmt::format(": the two clocks look {:.6f} s apart; shift the estimate by that much (s3m eval --offset, "
                       "EvalOptions::offset_s) if they are the same recording", g0 - e0);
  return "";
}

}  // namespace

TrajectoryEvaluation evaluate_trajectory(const io::Trajectory& gt, const io::Trajectory& est,
                                         const EvalOptions& options, const std::string& name) {
  options.validate();
  require(!gt.empty() && !est.empty(), "eval: empty trajectory (" + name + ")");
  TrajectoryEvaluation ev;
  ev.name = name;
  ev.gt_poses = gt.size();
  ev.est_poses = est.size();
  // 1. Associate estimate to ground truth by nearest timestamp within max_dt_s.
  ev.poses = match_poses(gt, est, options.max_dt_s, options.offset_s);
  ev.matched = ev.poses.t_s.size();
  if (ev.matched < 3)
    throw Error(fmt::format("eval '{}': only {} of {} estimated poses have a ground-truth pose within {} s "
                            "(estimate spans {:.6f}..{:.6f} s, ground truth {:.6f}..{:.6f} s); need at least 3{}",
                            name, ev.matched, est.size(), options.max_dt_s, est.front().t_s, est.back().t_s,
                            gt.front().t_s, gt.back().t_s, association_hint(gt, est, options.offset_s)));
  // 2.+3. Align (se3 / sim3 / none) and measure absolute errors.
  ev.ate = compute_ate(ev.poses, options.align);
  // 4. Relative errors, with the estimate's translations in ground-truth scale.
  ev.rpe = compute_rpe(ev.poses, options.rpe, ev.ate.alignment.scale);
  return ev;
}

}  // namespace s3m::eval
