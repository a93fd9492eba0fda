#include "s3m/navigation/planner.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <limits>
#include <memory>

#include <ompl/base/ProblemDefinition.h>
#include <ompl/base/ScopedState.h>
#include <ompl/base/SpaceInformation.h>
#include <ompl/base/spaces/RealVectorStateSpace.h>
#include <ompl/geometric/PathGeometric.h>
#include <ompl/geometric/PathSimplifier.h>
#include <ompl/geometric/planners/rrt/RRTConnect.h>
#include <ompl/util/Console.h>
#include <ompl/util/RandomNumbers.h>

#include "s3m/core/error.hpp"
#include "s3m/navigation/reachability.hpp"

namespace s3m::navigation {
namespace ob = ompl::base;
namespace og = ompl::geometric;

namespace {

std::string fmt_point(const Eigen::Vector3d& p) {
  char buf[96];
  std::snprintf(buf, sizeof buf, "(%.2f, %.2f, %.2f)", p.x(), p.y(), p.z());
  return buf;
}

Eigen::Vector3d to_point(const ob::State* s) {
  const auto* v = s->as<ob::RealVectorStateSpace::StateType>();
  return {v->values[0], v->values[1], v->values[2]};
}

// OMPL reports through its own console; our errors carry the reasons, so it stays quiet meanwhile.
struct QuietOmpl {
  ompl::msg::LogLevel before = ompl::msg::getLogLevel();
  QuietOmpl() { ompl::msg::setLogLevel(ompl::msg::LOG_NONE); }
  ~QuietOmpl() { ompl::msg::setLogLevel(before); }
};

ob::SpaceInformationPtr space_information(const DistanceField& field, double required) {
  auto space = std::make_shared<ob::RealVectorStateSpace>(3);
  ob::RealVectorBounds bounds(3);
  for (int i = 0; i < 3; ++i) {
    bounds.setLow(i, field.min_w()[i]);
    bounds.setHigh(i, std::max(field.max_w()[i], field.min_w()[i] + 1e-6));
  }
  space->setBounds(bounds);
  auto si = std::make_shared<ob::SpaceInformation>(space);
  si->setStateValidityChecker(
      [&field, required](const ob::State* s) { return field.clearance(to_point(s)) >= required; });
  // Motions are checked every half voxel, so no obstacle voxel is jumped over.
  si->setStateValidityCheckingResolution(0.5 * field.resolution() / space->getMaximumExtent());
  si->setup();
  return si;
}

// One RRTConnect run to one goal, shortcut and smoothed; empty when it found nothing in time.
std::vector<Eigen::Vector3d> attempt(const ob::SpaceInformationPtr& si, const Eigen::Vector3d& start,
                                     const Eigen::Vector3d& goal, const PlannerConfig& cfg) {
  ob::ScopedState<> s(si->getStateSpace()), g(si->getStateSpace());
  for (int i = 0; i < 3; ++i) s[i] = start[i], g[i] = goal[i];
  auto pdef = std::make_shared<ob::ProblemDefinition>(si);
  pdef->setStartAndGoalStates(s, g);
  og::RRTConnect rrt(si);
  rrt.setProblemDefinition(pdef);
  rrt.setup();
  if (rrt.solve(ob::timedPlannerTerminationCondition(cfg.time_limit_s)) != ob::PlannerStatus::EXACT_SOLUTION)
    return {};
  auto& path = *pdef->getSolutionPath()->as<og::PathGeometric>();
  og::PathSimplifier simplifier(si);
  simplifier.simplify(path, cfg.simplify_time_s);
  std::vector<Eigen::Vector3d> out;
  for (std::size_t i = 0; i < path.getStateCount(); ++i) out.push_back(to_point(path.getState(i)));
  return out;
}

// The grid search's voxel path from start to goal, shortcut and smoothed by OMPL's simplifier: it
// starts in the shortest corridor, where a sampled path may start in a longer one. Empty when a
// segment of it fails OMPL's motion check (the start and goal points sit off their voxel centres).
std::vector<Eigen::Vector3d> simplified_grid_path(const ob::SpaceInformationPtr& si,
                                                  const Eigen::Vector3d& start, const Eigen::Vector3d& goal,
                                                  std::vector<Eigen::Vector3d> cells,
                                                  const PlannerConfig& cfg) {
  cells.front() = start;
  cells.back() = goal;
  og::PathGeometric path(si);
  ob::ScopedState<> s(si->getStateSpace());
  for (const auto& p : cells) {
    for (int i = 0; i < 3; ++i) s[i] = p[i];
    path.append(s.get());
  }
  if (!path.check()) return {};
  og::PathSimplifier simplifier(si);
  simplifier.simplify(path, cfg.simplify_time_s);
  std::vector<Eigen::Vector3d> out;
  for (std::size_t i = 0; i < path.getStateCount(); ++i) out.push_back(to_point(path.getState(i)));
  return out;
}

}  // namespace

void PlannerConfig::validate() const {
  require(std::isfinite(radius_m) && radius_m >= 0.0, "planner: radius_m must be >= 0");
  require(std::isfinite(margin_m), "planner: margin_m must be a number");
  require(time_limit_s > 0.0 && simplify_time_s >= 0.0, "planner: time limits must be > 0");
  require(attempts >= 1, "planner: attempts must be >= 1");
}

double required_clearance(const DistanceField& field, const PlannerConfig& cfg) {
  return cfg.radius_m + (cfg.margin_m < 0.0 ? field.resolution() : cfg.margin_m);
}

std::string point_problem(const DistanceField& field, const PlannerConfig& cfg, const Eigen::Vector3d& p_w,
                          const std::string& what) {
  const double need = required_clearance(field, cfg);
  if (!field.contains(p_w))
    return what + " " + fmt_point(p_w) + " is outside the map's extent " + fmt_point(field.min_w()) + " .. " +
           fmt_point(field.max_w());
  const double c = field.clearance(p_w);
  if (c >= need) return "";
  const auto* node = field.tree().search(p_w.x(), p_w.y(), p_w.z());
  const std::string where = node == nullptr ? "is in unknown (unobserved) space"
                            : field.tree().isNodeOccupied(node)
                                ? "is inside an obstacle"
                                : "is too close to an obstacle or unknown space";
  char buf[160];
  std::snprintf(buf, sizeof buf, " (clearance %.3f m; needs %.3f m = radius %.3f m + margin %.3f m)", c, need,
                cfg.radius_m, need - cfg.radius_m);
  return what + " " + fmt_point(p_w) + " " + where + buf;
}

namespace {

// Indices into `usable` of the goals the start is connected to, nearest by grid path first; throws
// with the size of the start's free region when there is none.
std::vector<std::size_t> connected_goals(const DistanceField& field, const Eigen::Vector3d& start_w,
                                         const std::vector<Eigen::Vector3d>& usable_w, double need,
                                         const Reachability& reach) {
  std::vector<std::size_t> order;
  for (std::size_t k = 0; k < usable_w.size(); ++k)
    if (std::isfinite(reach.lengths_m[k])) order.push_back(k);
  std::stable_sort(order.begin(), order.end(),
                   [&](auto a, auto b) { return reach.lengths_m[a] < reach.lengths_m[b]; });
  if (!order.empty()) return order;
  char buf[320];
  std::snprintf(
      buf, sizeof buf,
      "none of the %zu usable goal point(s) is connected to the start %s through space with clearance "
      ">= %.3f m (unknown space counted as %s; the start's free region is %.2f m^3)",
      usable_w.size(), fmt_point(start_w).c_str(), need, to_string(field.config().unknown).c_str(),
      double(reach.voxels_reached) * std::pow(field.resolution(), 3));
  throw Error(buf);
}

}  // namespace

Path plan_path(const DistanceField& field, const Eigen::Vector3d& start_w,
               const std::vector<Eigen::Vector3d>& goals_w, const PlannerConfig& cfg) {
  cfg.validate();
  const auto t0 = std::chrono::steady_clock::now();
  // 1. The start and the usable goals.
  if (const auto problem = point_problem(field, cfg, start_w, "start"); !problem.empty())
    throw Error(problem);
  std::string goal_problem;
  std::vector<std::size_t> usable;
  std::vector<Eigen::Vector3d> usable_w;
  for (std::size_t i = 0; i < goals_w.size(); ++i) {
    const auto problem = point_problem(field, cfg, goals_w[i], "goal");
    if (problem.empty()) usable.push_back(i), usable_w.push_back(goals_w[i]);
    if (!problem.empty() && goal_problem.empty()) goal_problem = problem;
  }
  if (usable.empty()) throw Error(goals_w.empty() ? "no goal point given" : goal_problem);
  // 2. Goals the start is connected to, nearest by path first (a grid search over the field).
  const double need = required_clearance(field, cfg);
  const Reachability reach = grid_reachability(field, start_w, usable_w, need);
  const auto order = connected_goals(field, start_w, usable_w, need, reach);
  // 3. OMPL to the nearest goal; farther ones only while their grid distance could still beat the
  // best path. Each goal: the shortest of `attempts` RRTConnect paths and the grid search's path,
  // each shortcut and smoothed. Seeding OMPL's seed generator before each goal makes the planners'
  // and the simplifier's draws repeatable.
  const QuietOmpl quiet;
  const auto si = space_information(field, need);
  Path best;
  best.length_m = std::numeric_limits<double>::infinity();
  for (std::size_t n = 0; n < order.size() && n < 3 && reach.lengths_m[order[n]] < best.length_m; ++n) {
    const std::size_t k = order[n];
    ompl::RNG::setSeed(cfg.seed);
    for (int a = 0; a <= cfg.attempts; ++a) {
      auto waypoints = a == cfg.attempts
                           ? simplified_grid_path(si, start_w, usable_w[k], reach.paths_w[k], cfg)
                           : attempt(si, start_w, usable_w[k], cfg);
      if (waypoints.empty() || path_length(waypoints) >= best.length_m) continue;
      best.waypoints_w = std::move(waypoints);
      best.length_m = path_length(best.waypoints_w);
      best.goal_index = usable[k];
    }
  }
  if (best.waypoints_w.empty())  // the grid path is a path: only a failed motion check gets here
    throw Error(
        "no path found from " + fmt_point(start_w) + " to the " + std::to_string(order.size()) +
        " goal point(s) connected to it: OMPL's motion check refused the grid path and RRTConnect found "
        "none in time; try a larger --time-limit");
  best.min_clearance_m = min_clearance(field, best.waypoints_w);
  best.planning_time_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  return best;
}

double path_length(const std::vector<Eigen::Vector3d>& waypoints_w) {
  double length = 0.0;
  for (std::size_t i = 1; i < waypoints_w.size(); ++i) length += (waypoints_w[i] - waypoints_w[i - 1]).norm();
  return length;
}

double min_clearance(const DistanceField& field, const std::vector<Eigen::Vector3d>& waypoints_w,
                     double step_m) {
  double lowest = std::numeric_limits<double>::infinity();
  for (std::size_t i = 0; i < waypoints_w.size(); ++i) {
    lowest = std::min(lowest, field.clearance(waypoints_w[i]));
    if (i == 0) continue;
    const Eigen::Vector3d d = waypoints_w[i] - waypoints_w[i - 1];
    const int n = int(std::ceil(d.norm() / step_m));
    for (int k = 1; k < n; ++k)
      lowest = std::min(lowest, field.clearance(waypoints_w[i - 1] + d * (double(k) / n)));
  }
  return lowest;
}

}  // namespace s3m::navigation
