// `s3m plan map.ot --from x,y,z (--to-class bed | --to x,y,z) [--radius 0.3] [--near 0.5]
// [--out path.json] [--tum path.txt]`: a collision-free path for a spherical robot through the
// map's distance field, to a free point near the nearest (by path) instance of a class or to a point.
#include <cstdio>
#include <iostream>
#include <optional>

#include <nlohmann/json.hpp>

#include "commands.hpp"
#include "s3m/core/atomic_file.hpp"
#include "s3m/core/error.hpp"
#include "s3m/mapping/map_io.hpp"
#include "s3m/navigation/goals.hpp"
#include "s3m/navigation/path_io.hpp"
#include "s3m/navigation/planner.hpp"

namespace s3m::apps {

namespace {

struct PlanOptions {
  std::string map, to_class, out, tum, unknown = "occupied";
  std::vector<double> from, to;
  double near_m = 0.5, max_distance_m = 2.0;
  navigation::PlannerConfig planner;
  std::size_t min_voxels = 10;
  bool json = false;
};

nlohmann::json to_json(const Eigen::Vector3d& v) { return {v.x(), v.y(), v.z()}; }
Eigen::Vector3d point(const std::vector<double>& v) { return {v[0], v[1], v[2]}; }

ClassId class_by_name(const mapping::SemanticOcTree& tree, const std::string& name, std::size_t min_voxels) {
  const int id = tree.classes().find(name);
  if (id >= 0) return ClassId(id);
  throw Error("plan: unknown class '" + name +
              "'; classes present in the map: " + navigation::classes_present(tree, min_voxels));
}

void run_plan(PlanOptions o) {
  require(o.from.size() == 3, "plan: --from needs three coordinates x,y,z [m]");
  require(o.to_class.empty() != o.to.empty(), "plan: give exactly one of --to-class CLASS or --to x,y,z");
  require(o.to.empty() || o.to.size() == 3, "plan: --to needs three coordinates x,y,z [m]");
  // 1. Map and distance field.
  auto tree = mapping::load_semantic_map(o.map);
  navigation::DistanceFieldConfig fc;
  fc.unknown = navigation::unknown_space_from_string(o.unknown);
  fc.max_distance_m = o.max_distance_m;
  const navigation::DistanceField field(*tree, fc);
  const Eigen::Vector3d start = point(o.from);
  nlohmann::json result = {{"map", o.map},
                           {"from", to_json(start)},
                           {"radius_m", o.planner.radius_m},
                           {"required_clearance_m", required_clearance(field, o.planner)},
                           {"unknown_space", o.unknown},
                           {"seed", o.planner.seed}};
  // 2. Goal points: near the class's nearest instances, or the given point.
  std::optional<navigation::ClassGoal> class_goal;
  std::vector<Eigen::Vector3d> goals{o.to.empty() ? Eigen::Vector3d::Zero() : point(o.to)};
  if (!o.to_class.empty()) {
    if (const auto problem = navigation::point_problem(field, o.planner, start, "start"); !problem.empty())
      throw Error("plan: " + problem);
    navigation::ClassGoalConfig gc;
    gc.near_m = o.near_m;
    gc.clearance_m = required_clearance(field, o.planner);
    gc.min_voxels = o.min_voxels;
    const ClassId id = class_by_name(*tree, o.to_class, o.min_voxels);
    navigation::ClassGoal goal;
    try {
      goal = navigation::class_goal(field, id, start, gc);
    } catch (const Error& e) {
      throw Error(std::string("plan: ") + e.what());
    }
    if (goal.goals_w.empty())
      throw Error("plan: no free point within " + std::to_string(o.near_m) + " m of the " +
                  std::to_string(goal.instances.size()) + " nearest " + o.to_class +
                  " instance(s) (nearest centroid " + to_json(goal.instances.front().centroid_w).dump() +
                  ") has the clearance " + std::to_string(gc.clearance_m) +
                  " m; try a larger --near or a smaller --radius");
    goals = goal.goals_w;
    class_goal = goal;
    result["class"] = o.to_class;
    result["near_m"] = o.near_m;
  }
  // 3. Path (throws with the reason when there is none).
  navigation::Path path;
  try {
    path = navigation::plan_path(field, start, goals, o.planner);
  } catch (const Error& e) {
    throw Error(std::string("plan: ") + e.what());
  }
  result["to"] = to_json(path.waypoints_w.back());
  if (class_goal) {
    const auto& inst = class_goal->instances[class_goal->goal_instance[path.goal_index]];
    result["instance"] = {{"centroid_m", to_json(inst.centroid_w)},
                          {"bbox_min_m", to_json(inst.bbox_min_w)},
                          {"bbox_max_m", to_json(inst.bbox_max_w)},
                          {"voxels", inst.voxels}};
  }
  result["waypoints_m"] = nlohmann::json::array();
  for (const auto& p : path.waypoints_w) result["waypoints_m"].push_back(to_json(p));
  result["length_m"] = path.length_m;
  result["min_clearance_m"] = path.min_clearance_m;
  result["planning_time_s"] = path.planning_time_s;
  result["planner"] = "RRTConnect and the grid path, shortcut + B-spline (OMPL)";
  // 4. Outputs.
  if (!o.out.empty()) write_text_atomic(o.out, result.dump(2) + "\n");
  if (!o.tum.empty()) navigation::write_path_tum(o.tum, path.waypoints_w);
  if (o.json) {
    std::cout << result.dump(2) << "\n";
    return;
  }
  std::printf("plan: %zu waypoints to (%.3f, %.3f, %.3f), length %.3f m, min clearance %.3f m, %.3f s\n",
              path.waypoints_w.size(), path.waypoints_w.back().x(), path.waypoints_w.back().y(),
              path.waypoints_w.back().z(), path.length_m, path.min_clearance_m, path.planning_time_s);
  if (!o.out.empty()) std::printf("plan: wrote %s\n", o.out.c_str());
  if (!o.tum.empty()) std::printf("plan: wrote %s (TUM poses)\n", o.tum.c_str());
}

}  // namespace

void register_plan(CLI::App& app) {
  auto opts = std::make_shared<PlanOptions>();
  auto* cmd = app.add_subcommand("plan", "Collision-free path through a semantic map to a class or a point");
  cmd->add_option("map", opts->map, "semantic map (.ot written by s3m run); or the run's --out folder")
      ->required()
      ->transform(map_or_run_folder())
      ->check(CLI::ExistingFile);
  cmd->add_option("--from", opts->from, "x,y,z [m]: start (world frame)")
      ->required()
      ->expected(3)
      ->delimiter(',');
  cmd->add_option("--to-class", opts->to_class, "class name: go near its nearest instance (by path)");
  cmd->add_option("--to", opts->to, "x,y,z [m]: go to this point")->expected(3)->delimiter(',');
  cmd->add_option("--radius", opts->planner.radius_m, "robot radius [m]")->capture_default_str();
  cmd->add_option("--margin", opts->planner.margin_m, "clearance on top of the radius [m]; < 0: one voxel")
      ->capture_default_str();
  cmd->add_option("--near", opts->near_m, "goal within this distance of the class instance [m]")
      ->capture_default_str();
  cmd->add_option("--unknown", opts->unknown, "unknown space counts as: occupied or free")
      ->check(CLI::IsMember({"occupied", "free"}))
      ->capture_default_str();
  cmd->add_option("--max-distance", opts->max_distance_m, "distance field saturation [m]")
      ->capture_default_str();
  cmd->add_option("--time-limit", opts->planner.time_limit_s, "RRTConnect time per goal point [s]")
      ->capture_default_str();
  cmd->add_option("--seed", opts->planner.seed, "random seed (same seed, same path)")->capture_default_str();
  cmd->add_option("--min-voxels", opts->min_voxels, "ignore class instances smaller than this")
      ->capture_default_str();
  cmd->add_option("--out", opts->out, "write the path as JSON (waypoints, length, min clearance)");
  cmd->add_option("--tum", opts->tum, "write the path as TUM poses (t = arc length at 1 m/s)");
  cmd->add_flag("--json", opts->json, "print JSON instead of text");
  cmd->callback([opts] { run_plan(*opts); });
}

}  // namespace s3m::apps
