#pragma once
// Goal points for "go to the <class>": free points near the object instances of a class
// (mapping::object_instances), for plan_path, which goes to the one nearest by path. World frame,
// metres.
#include <string>
#include <vector>

#include <Eigen/Core>

#include "s3m/mapping/queries.hpp"
#include "s3m/navigation/distance_field.hpp"

namespace s3m::navigation {

struct ClassGoalConfig {
  double near_m = 0.5;            // a goal lies within this distance of the instance's voxels
  double clearance_m = 0.35;      // and has at least this clearance (the planner's radius + margin)
  std::size_t min_voxels = 10;    // smaller instances are specks, not objects (as `s3m query`)
  std::size_t max_goals = 24;     // goal points per instance, nearest to the start first
  std::size_t max_instances = 4;  // instances considered, nearest to the start (straight line) first
  double goal_spacing_m = 0.1;    // goal points are at least this far apart
  void validate() const;
};

struct ClassGoal {
  std::vector<mapping::ObjectInstance> instances;  // nearest to the start (bounding box) first
  std::vector<Eigen::Vector3d> goals_w;            // empty when no point near any instance is free
  std::vector<std::size_t> goal_instance;          // per goal point: its instance in `instances`
};

// The instances of `label` nearest to start_w (distance to their bounding boxes) and the free points
// around each. Throws s3m::Error when the map has no instance of the class, naming the classes present.
ClassGoal class_goal(const DistanceField& field, ClassId label, const Eigen::Vector3d& start_w,
                     const ClassGoalConfig& cfg);

// "chair (3 instances), table (1 instance)": the classes with instances of >= min_voxels voxels.
std::string classes_present(const mapping::SemanticOcTree& tree, std::size_t min_voxels);

}  // namespace s3m::navigation
