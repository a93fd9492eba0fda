#pragma once
// Collision-free paths for a spherical robot through a DistanceField, with OMPL: RRTConnect on the
// field's box with clearance >= radius + margin as the validity check and motions checked every
// half voxel, then OMPL's shortcutting and B-spline smoothing; a grid search over the field picks
// the goal and its path, simplified the same way, competes. World frame, metres.
#include <cstdint>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "s3m/navigation/distance_field.hpp"

namespace s3m::navigation {

struct PlannerConfig {
  double radius_m = 0.3;          // robot's bounding sphere
  double margin_m = -1.0;         // clearance on top of radius_m; < 0: one voxel of the field (the field
                                  // measures between voxel centres, a point may sit anywhere in its voxel)
  double time_limit_s = 1.0;      // RRTConnect per goal point
  double simplify_time_s = 0.25;  // shortcutting and smoothing per attempt
  int attempts = 2;               // independent RRTConnect runs per goal point; the shortest path is kept
  std::uint32_t seed = 1;         // OMPL's random seed: same map, same query, same path
  void validate() const;
};

struct Path {
  std::vector<Eigen::Vector3d> waypoints_w;  // start first, goal last [m]
  double length_m = 0.0;
  double min_clearance_m = 0.0;  // smallest field clearance sampled every centimetre along it
  double planning_time_s = 0.0;
  std::size_t goal_index = 0;  // which of the goal points it reaches
};

// Clearance a point needs to be valid: radius plus margin [m].
double required_clearance(const DistanceField& field, const PlannerConfig& cfg);

// Why a point cannot be used ("", if it can): outside the field, in unknown space, inside an
// obstacle or too close to one, with its clearance. `what` names it in the message ("start").
std::string point_problem(const DistanceField& field, const PlannerConfig& cfg, const Eigen::Vector3d& p_w,
                          const std::string& what);

// A path from start_w to one of goals_w: a grid search over the field finds the goals the start is
// connected to, OMPL plans to the nearest of them by that search (and to up to two more while they
// could give a shorter path), and the shortest path is returned. Throws s3m::Error when the start is
// unusable, no goal is usable or connected, or OMPL found no path in time (saying what was tried).
Path plan_path(const DistanceField& field, const Eigen::Vector3d& start_w,
               const std::vector<Eigen::Vector3d>& goals_w, const PlannerConfig& cfg);

// Length [m] and smallest clearance [m] of a polyline, the latter sampled every step_m.
double path_length(const std::vector<Eigen::Vector3d>& waypoints_w);
double min_clearance(const DistanceField& field, const std::vector<Eigen::Vector3d>& waypoints_w,
                     double step_m = 0.01);

}  // namespace s3m::navigation
