#include "s3m/slam/slam_config.hpp"

#include <vector>

#include "s3m/core/error.hpp"
#include "s3m/core/yaml_util.hpp"

namespace s3m::slam {
namespace {

void read_orb(const YAML::Node& n, features::OrbConfig& c, const std::string& ctx) {
  if (!n) return;
  check_known_keys(n, {"n_features", "scale_factor", "n_levels", "ini_fast_threshold", "min_fast_threshold",
                       "cell_px", "parallel_levels"}, ctx);
  yaml_get(n, "n_features", c.n_features, ctx);
  yaml_get(n, "scale_factor", c.scale_factor, ctx);
  yaml_get(n, "n_levels", c.n_levels, ctx);
  yaml_get(n, "ini_fast_threshold", c.ini_fast_threshold, ctx);
  yaml_get(n, "min_fast_threshold", c.min_fast_threshold, ctx);
  yaml_get(n, "cell_px", c.cell_px, ctx);
  yaml_get(n, "parallel_levels", c.parallel_levels, ctx);
}

void read_features(const YAML::Node& n, features::FeatureConfig& c, const std::string& ctx) {
  if (!n) return;
  check_known_keys(n, {"orb", "min_depth_m", "max_depth_m", "depth_discontinuity_ratio", "depth_window_px"}, ctx);
  read_orb(n["orb"], c.orb, ctx);
  yaml_get(n, "min_depth_m", c.min_depth_m, ctx);
  yaml_get(n, "max_depth_m", c.max_depth_m, ctx);
  yaml_get(n, "depth_discontinuity_ratio", c.depth_discontinuity_ratio, ctx);
  yaml_get(n, "depth_window_px", c.depth_window_px, ctx);
}

void read_tracker(const YAML::Node& n, TrackerConfig& c, const std::string& ctx) {
  if (!n) return;
  check_known_keys(n, {"pose_rounds", "pose_iterations", "close_depth_m", "motion_radius_px", "min_motion_matches",
                       "min_pose_inliers", "local_radius_factor", "min_local_inliers", "max_frames_between_keyframes",
                       "min_frames_between_keyframes", "keyframe_ref_ratio", "close_tracked_min",
                       "close_untracked_min", "max_pending_keyframes", "min_init_depth_points"}, ctx);
  yaml_get(n, "pose_rounds", c.pose.rounds, ctx);
  yaml_get(n, "pose_iterations", c.pose.iterations, ctx);
  yaml_get(n, "close_depth_m", c.close_depth_m, ctx);
  yaml_get(n, "motion_radius_px", c.motion_radius_px, ctx);
  yaml_get(n, "min_motion_matches", c.min_motion_matches, ctx);
  yaml_get(n, "min_pose_inliers", c.min_pose_inliers, ctx);
  yaml_get(n, "local_radius_factor", c.local_radius_factor, ctx);
  yaml_get(n, "min_local_inliers", c.min_local_inliers, ctx);
  yaml_get(n, "max_frames_between_keyframes", c.max_frames_between_keyframes, ctx);
  yaml_get(n, "min_frames_between_keyframes", c.min_frames_between_keyframes, ctx);
  yaml_get(n, "keyframe_ref_ratio", c.keyframe_ref_ratio, ctx);
  yaml_get(n, "close_tracked_min", c.close_tracked_min, ctx);
  yaml_get(n, "close_untracked_min", c.close_untracked_min, ctx);
  yaml_get(n, "max_pending_keyframes", c.max_pending_keyframes, ctx);
  yaml_get(n, "min_init_depth_points", c.min_init_depth_points, ctx);
}

void read_mapper(const YAML::Node& n, MapperConfig& c, const std::string& ctx) {
  if (!n) return;
  check_known_keys(n, {"close_depth_m", "min_new_points", "min_found_ratio", "fuse_neighbours", "local_ba",
                       "cull_keyframes", "redundant_ratio", "snapshot_keyframes", "final_global_ba", "ba"},
                   ctx);
  yaml_get(n, "close_depth_m", c.close_depth_m, ctx);
  yaml_get(n, "min_new_points", c.min_new_points, ctx);
  yaml_get(n, "min_found_ratio", c.min_found_ratio, ctx);
  yaml_get(n, "fuse_neighbours", c.fuse_neighbours, ctx);
  yaml_get(n, "local_ba", c.local_ba, ctx);
  yaml_get(n, "cull_keyframes", c.cull_keyframes, ctx);
  yaml_get(n, "redundant_ratio", c.redundant_ratio, ctx);
  yaml_get(n, "snapshot_keyframes", c.snapshot_keyframes, ctx);
  yaml_get(n, "final_global_ba", c.final_global_ba, ctx);
  if (const auto b = n["ba"]) {
    check_known_keys(b, {"first_iterations", "second_iterations", "max_local_keyframes", "global_iterations"}, ctx);
    yaml_get(b, "first_iterations", c.ba.first_iterations, ctx);
    yaml_get(b, "second_iterations", c.ba.second_iterations, ctx);
    yaml_get(b, "max_local_keyframes", c.ba.max_local_keyframes, ctx);
    yaml_get(b, "global_iterations", c.ba.global_iterations, ctx);
  }
}

SE3 read_pose(const YAML::Node& n, const std::string& ctx) {
  check_known_keys(n, {"t", "q"}, ctx);
  std::vector<double> t{0, 0, 0}, q{0, 0, 0, 1};
  yaml_get(n, "t", t, ctx);
  yaml_get(n, "q", q, ctx);
  if (t.size() != 3 || q.size() != 4)
    throw ParseError(ctx, n.Mark().line + 1, "bad T_c_r", "t: [x, y, z] and q: [qx, qy, qz, qw]");
  const Quat quat(q[3], q[0], q[1], q[2]);
  if (std::abs(quat.norm() - 1.0) > 1e-3)
    throw ParseError(ctx, n.Mark().line + 1, "T_c_r quaternion is not unit length", "a unit quaternion");
  return make_se3(Vec3(t[0], t[1], t[2]), quat);
}

}  // namespace

void PlaceRecognitionConfig::validate() const {
  loop.validate();
  reloc.validate();
  require(snapshot_keyframes >= 1, "slam.places.snapshot_keyframes must be >= 1");
}

void SlamConfig::validate() const {
  features.validate();
  tracker.validate();
  mapper.validate();
  places.validate();
  require(queue_capacity >= tracker.max_pending_keyframes + 2,
          "slam.queue_capacity must be >= tracker.max_pending_keyframes + 2 = " +
              std::to_string(tracker.max_pending_keyframes + 2) + " (got " + std::to_string(queue_capacity) + ")");
  require(T_c_r.matrix().allFinite(), "slam.T_c_r must be finite");
}

SlamConfig slam_config_from_yaml(const YAML::Node& node, const std::string& ctx) {
  SlamConfig c;
  if (!node || node.IsNull()) return c;
  check_known_keys(node, {"features", "tracker", "mapper", "T_c_r", "threaded", "queue_capacity"}, ctx);
  read_features(node["features"], c.features, ctx);
  read_tracker(node["tracker"], c.tracker, ctx);
  read_mapper(node["mapper"], c.mapper, ctx);
  if (node["T_c_r"]) c.T_c_r = read_pose(node["T_c_r"], ctx);
  yaml_get(node, "threaded", c.threaded, ctx);
  yaml_get(node, "queue_capacity", c.queue_capacity, ctx);
  try {
    c.validate();
  } catch (const Error& e) {
    throw ParseError(ctx, 0, e.what(), "values inside the documented ranges");
  }
  return c;
}

SlamConfig load_slam_config(const std::string& path) {
  const YAML::Node root = load_yaml_file(path);
  return slam_config_from_yaml(root["slam"] ? root["slam"] : root, path);
}

}  // namespace s3m::slam
