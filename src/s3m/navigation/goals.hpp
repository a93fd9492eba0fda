#pragma once
// Goal points for "go to the <class>": free points near the nearest object instance of a class
// (mapping::object_instances), for plan_path to try in order. World frame, metres.
#include <string>
#include <vector>

#include <Eigen/Core>

#include "s3m/mapping/queries.hpp"
#include "s3m/navigation/distance_field.hpp"

namespace s3m::navigation {

struct ClassGoalConfig {
  double near_m = 0.5;           // a goal lies within this distance of the instance's voxels
  double clearance_m = 0.35;     // and has at least this clearance (the planner's radius + margin)
  std::size_t min_voxels = 10;   // smaller instances are specks, not objects (as `s3m query`)
  std::size_t max_goals = 8;     // goal points returned, nearest to the start first
  double goal_spacing_m = 0.25;  // goal points are at least this far apart
  void validate() const;
};

struct ClassGoal {
  mapping::ObjectInstance instance;      // the instance nearest to the start
  std::vector<Eigen::Vector3d> goals_w;  // nearest to the start first; empty when none is free
};

// The instance of `label` nearest to start_w (distance to its bounding box) and the free points
// around it. Throws s3m::Error when the map has no instance of the class, naming the classes present.
ClassGoal class_goal(const DistanceField& field, ClassId label, const Eigen::Vector3d& start_w,
                     const ClassGoalConfig& cfg);

// "chair (3 instances), table (1 instance)": the classes with instances of >= min_voxels voxels.
std::string classes_present(const mapping::SemanticOcTree& tree, std::size_t min_voxels);

}  // namespace s3m::navigation
