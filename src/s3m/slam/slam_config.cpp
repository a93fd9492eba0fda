#include "s3m/slam/slam_config.hpp"

#include <vector>

#include "s3m/core/error.hpp"
#include "s3m/core/yaml_util.hpp"

namespace s3m::slam {
namespace {

void read_orb(const YAML::Node& n, features::OrbConfig& c, const std::string& ctx) {
  if (!n) return;
  check_known_keys(n,
                   {"n_features", "scale_factor", "n_levels", "ini_fast_threshold", "min_fast_threshold",
                    "cell_px", "parallel_levels", "level_sigma_exponent"},
                   ctx);
  yaml_get(n, "n_features", c.n_features, ctx);
  yaml_get(n, "scale_factor", c.scale_factor, ctx);
  yaml_get(n, "n_levels", c.n_levels, ctx);
  yaml_get(n, "ini_fast_threshold", c.ini_fast_threshold, ctx);
  yaml_get(n, "min_fast_threshold", c.min_fast_threshold, ctx);
  yaml_get(n, "cell_px", c.cell_px, ctx);
  yaml_get(n, "parallel_levels", c.parallel_levels, ctx);
  yaml_get(n, "level_sigma_exponent", c.level_sigma_exponent, ctx);
}

void read_depth_noise(const YAML::Node& n, features::DepthNoiseConfig& c, const std::string& ctx) {
  if (!n) return;
  check_known_keys(n, {"model", "sigma0_m", "k_per_m"}, ctx);
  yaml_get(n, "model", c.model, ctx);
  yaml_get(n, "sigma0_m", c.sigma0_m, ctx);
  yaml_get(n, "k_per_m", c.k_per_m, ctx);
}

void read_features(const YAML::Node& n, features::FeatureConfig& c, const std::string& ctx) {
  if (!n) return;
  check_known_keys(
      n, {"orb", "min_depth_m", "max_depth_m", "depth_discontinuity_ratio", "depth_window_px", "depth_noise"},
      ctx);
  read_orb(n["orb"], c.orb, ctx);
  read_depth_noise(n["depth_noise"], c.depth_noise, ctx);
  yaml_get(n, "min_depth_m", c.min_depth_m, ctx);
  yaml_get(n, "max_depth_m", c.max_depth_m, ctx);
  yaml_get(n, "depth_discontinuity_ratio", c.depth_discontinuity_ratio, ctx);
  yaml_get(n, "depth_window_px", c.depth_window_px, ctx);
}

void read_tracker(const YAML::Node& n, TrackerConfig& c, const std::string& ctx) {
  if (!n) return;
  check_known_keys(n,
                   {"pose_rounds",
                    "pose_iterations",
                    "close_depth_m",
                    "motion_radius_px",
                    "min_motion_matches",
                    "min_pose_inliers",
                    "wide_match_ratio",
                    "local_radius_factor",
                    "min_local_inliers",
                    "max_frames_between_keyframes",
                    "min_frames_between_keyframes",
                    "keyframe_ref_ratio",
                    "keyframe_decay_ratio",
                    "keyframe_max_deg",
                    "keyframe_max_m",
                    "close_tracked_min",
                    "close_untracked_min",
                    "max_pending_keyframes",
                    "min_init_depth_points",
                    "anchor_keyframes",
                    "coast_frames",
                    "bridge_deg",
                    "bridge_m",
                    "bridge_min_inliers",
                    "odometry_frames",
                    "odometry_deg",
                    "odometry_m",
                    "odometry_agree_fraction",
                    "odometry_min_colour_agreement",
                    "odometry_downsample",
                    "odometry_max_depth_diff_m",
                    "odometry_min_observed_ratio",
                    "odometry_max_step_m",
                    "odometry_max_step_deg",
                    "odometry_gap_max_depth_diff_m"},
                   ctx);
  yaml_get(n, "pose_rounds", c.pose.rounds, ctx);
  yaml_get(n, "pose_iterations", c.pose.iterations, ctx);
  yaml_get(n, "close_depth_m", c.close_depth_m, ctx);
  yaml_get(n, "motion_radius_px", c.motion_radius_px, ctx);
  yaml_get(n, "min_motion_matches", c.min_motion_matches, ctx);
  yaml_get(n, "min_pose_inliers", c.min_pose_inliers, ctx);
  yaml_get(n, "wide_match_ratio", c.wide_match_ratio, ctx);
  yaml_get(n, "local_radius_factor", c.local_radius_factor, ctx);
  yaml_get(n, "min_local_inliers", c.min_local_inliers, ctx);
  yaml_get(n, "max_frames_between_keyframes", c.max_frames_between_keyframes, ctx);
  yaml_get(n, "min_frames_between_keyframes", c.min_frames_between_keyframes, ctx);
  yaml_get(n, "keyframe_ref_ratio", c.keyframe_ref_ratio, ctx);
  yaml_get(n, "keyframe_decay_ratio", c.keyframe_decay_ratio, ctx);
  yaml_get(n, "keyframe_max_deg", c.keyframe_max_deg, ctx);
  yaml_get(n, "keyframe_max_m", c.keyframe_max_m, ctx);
  yaml_get(n, "close_tracked_min", c.close_tracked_min, ctx);
  yaml_get(n, "close_untracked_min", c.close_untracked_min, ctx);
  yaml_get(n, "max_pending_keyframes", c.max_pending_keyframes, ctx);
  yaml_get(n, "min_init_depth_points", c.min_init_depth_points, ctx);
  yaml_get(n, "anchor_keyframes", c.anchor_keyframes, ctx);
  yaml_get(n, "coast_frames", c.coast_frames, ctx);
  yaml_get(n, "bridge_deg", c.bridge_deg, ctx);
  yaml_get(n, "bridge_m", c.bridge_m, ctx);
  yaml_get(n, "bridge_min_inliers", c.bridge_min_inliers, ctx);
  yaml_get(n, "odometry_frames", c.odometry_frames, ctx);
  yaml_get(n, "odometry_deg", c.odometry_deg, ctx);
  yaml_get(n, "odometry_m", c.odometry_m, ctx);
  yaml_get(n, "odometry_agree_fraction", c.odometry_agree_fraction, ctx);
  yaml_get(n, "odometry_min_colour_agreement", c.odometry_min_colour_agreement, ctx);
  yaml_get(n, "odometry_downsample", c.odometry.downsample, ctx);
  yaml_get(n, "odometry_max_depth_diff_m", c.odometry.max_depth_diff_m, ctx);
  yaml_get(n, "odometry_min_observed_ratio", c.odometry.min_observed_ratio, ctx);
  yaml_get(n, "odometry_max_step_m", c.odometry.max_step_m, ctx);
  yaml_get(n, "odometry_max_step_deg", c.odometry.max_step_deg, ctx);
  yaml_get(n, "odometry_gap_max_depth_diff_m", c.odometry.gap_max_depth_diff_m, ctx);
}

void read_ba(const YAML::Node& n, BaConfig& c, const std::string& ctx) {
  if (!n) return;
  check_known_keys(
      n,
      {"first_iterations", "second_iterations", "chi2_mono", "chi2_stereo", "max_local_keyframes",
       "global_iterations", "max_keyframe_step_deg", "max_keyframe_step_m"},
      ctx);
  yaml_get(n, "first_iterations", c.first_iterations, ctx);
  yaml_get(n, "second_iterations", c.second_iterations, ctx);
  yaml_get(n, "chi2_mono", c.chi2_mono, ctx);
  yaml_get(n, "chi2_stereo", c.chi2_stereo, ctx);
  yaml_get(n, "max_keyframe_step_deg", c.max_keyframe_step_deg, ctx);
  yaml_get(n, "max_keyframe_step_m", c.max_keyframe_step_m, ctx);
  yaml_get(n, "max_local_keyframes", c.max_local_keyframes, ctx);
  yaml_get(n, "global_iterations", c.global_iterations, ctx);
}

void read_dense_links(const YAML::Node& n, DenseLinkConfig& c, const std::string& ctx) {
  if (!n) return;
  check_known_keys(
      n,
      {"enabled", "sigma_deg", "sigma_m", "max_deg", "max_m", "downsample", "max_median_deg", "max_median_m"},
      ctx);
  yaml_get(n, "enabled", c.enabled, ctx);
  yaml_get(n, "sigma_deg", c.sigma_deg, ctx);
  yaml_get(n, "sigma_m", c.sigma_m, ctx);
  yaml_get(n, "max_deg", c.max_deg, ctx);
  yaml_get(n, "max_m", c.max_m, ctx);
  yaml_get(n, "downsample", c.downsample, ctx);
  yaml_get(n, "max_median_deg", c.max_median_deg, ctx);
  yaml_get(n, "max_median_m", c.max_median_m, ctx);
}

void read_mapper(const YAML::Node& n, MapperConfig& c, const std::string& ctx) {
  if (!n) return;
  check_known_keys(
      n,
      {"close_depth_m", "min_new_points", "min_found_ratio", "fuse_neighbours", "local_ba", "cull_keyframes",
       "redundant_ratio", "snapshot_keyframes", "final_global_ba", "dense_links", "ba"},
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
  read_dense_links(n["dense_links"], c.dense_links, ctx);
  read_ba(n["ba"], c.ba, ctx);
}

// Loop closing's sub-structs, one reader each.
void read_detector(const YAML::Node& n, LoopDetectorConfig& c, const std::string& ctx) {
  if (!n) return;
  check_known_keys(n, {"min_common_words_ratio", "group_score_ratio", "group_neighbours", "consistency"},
                   ctx);
  yaml_get(n, "min_common_words_ratio", c.min_common_words_ratio, ctx);
  yaml_get(n, "group_score_ratio", c.group_score_ratio, ctx);
  yaml_get(n, "group_neighbours", c.group_neighbours, ctx);
  yaml_get(n, "consistency", c.consistency, ctx);
}

void read_bow_match(const YAML::Node& n, features::BowMatchConfig& c, const std::string& ctx) {
  if (!n) return;
  check_known_keys(n, {"max_hamming", "ratio"}, ctx);
  yaml_get(n, "max_hamming", c.max_hamming, ctx);
  yaml_get(n, "ratio", c.ratio, ctx);
}

void read_ransac(const YAML::Node& n, Se3RansacConfig& c, const std::string& ctx) {
  if (!n) return;
  check_known_keys(n, {"max_iterations", "threshold_m", "depth_ratio", "min_inliers", "seed"}, ctx);
  yaml_get(n, "max_iterations", c.max_iterations, ctx);
  yaml_get(n, "threshold_m", c.threshold_m, ctx);
  yaml_get(n, "depth_ratio", c.depth_ratio, ctx);
  yaml_get(n, "min_inliers", c.min_inliers, ctx);
  yaml_get(n, "seed", c.seed, ctx);
}

void read_pose_graph(const YAML::Node& n, PoseGraphConfig& c, const std::string& ctx) {
  if (!n) return;
  check_known_keys(n, {"max_iterations", "loop_huber"}, ctx);
  yaml_get(n, "max_iterations", c.max_iterations, ctx);
  yaml_get(n, "loop_huber", c.loop_huber, ctx);
}

void read_pnp(const YAML::Node& n, PnpConfig& c, const std::string& ctx) {
  if (!n) return;
  check_known_keys(n, {"iterations", "reprojection_px", "confidence", "min_inliers"}, ctx);
  yaml_get(n, "iterations", c.iterations, ctx);
  yaml_get(n, "reprojection_px", c.reprojection_px, ctx);
  yaml_get(n, "confidence", c.confidence, ctx);
  yaml_get(n, "min_inliers", c.min_inliers, ctx);
}

// LoopConfig's keys sit at the top of the `loop_closing:` section (next to enabled, ...).
const std::vector<std::string> kLoopKeys = {"min_keyframes",
                                            "min_keyframes_since_loop",
                                            "direct_level",
                                            "detector",
                                            "bow_match",
                                            "min_bow_matches",
                                            "ransac",
                                            "loop_group_size",
                                            "search_radius_factor",
                                            "min_projection_matches",
                                            "essential_min_weight",
                                            "pose_graph",
                                            "global_ba",
                                            "ba"};

void read_loop(const YAML::Node& n, LoopConfig& c, const std::string& ctx) {
  yaml_get(n, "min_keyframes", c.min_keyframes, ctx);
  yaml_get(n, "min_keyframes_since_loop", c.min_keyframes_since_loop, ctx);
  yaml_get(n, "direct_level", c.direct_level, ctx);
  read_detector(n["detector"], c.detector, ctx);
  read_bow_match(n["bow_match"], c.bow_match, ctx);
  yaml_get(n, "min_bow_matches", c.min_bow_matches, ctx);
  read_ransac(n["ransac"], c.ransac, ctx);
  yaml_get(n, "loop_group_size", c.loop_group_size, ctx);
  yaml_get(n, "search_radius_factor", c.search_radius_factor, ctx);
  yaml_get(n, "min_projection_matches", c.min_projection_matches, ctx);
  yaml_get(n, "essential_min_weight", c.essential_min_weight, ctx);
  read_pose_graph(n["pose_graph"], c.pose_graph, ctx);
  yaml_get(n, "global_ba", c.global_ba, ctx);
  read_ba(n["ba"], c.ba, ctx);
}

void read_reloc(const YAML::Node& n, RelocConfig& c, const std::string& ctx) {
  if (!n) return;
  check_known_keys(
      n,
      {"max_candidates", "min_score_ratio", "bow_match", "min_bow_matches", "pnp", "local_keyframes",
       "wide_radius_factor", "search_radius_factor", "min_final_inliers", "snapshot_keyframes"},
      ctx);
  yaml_get(n, "max_candidates", c.max_candidates, ctx);
  yaml_get(n, "min_score_ratio", c.min_score_ratio, ctx);
  read_bow_match(n["bow_match"], c.bow_match, ctx);
  yaml_get(n, "min_bow_matches", c.min_bow_matches, ctx);
  read_pnp(n["pnp"], c.pnp, ctx);
  yaml_get(n, "local_keyframes", c.local_keyframes, ctx);
  yaml_get(n, "wide_radius_factor", c.wide_radius_factor, ctx);
  yaml_get(n, "search_radius_factor", c.search_radius_factor, ctx);
  yaml_get(n, "min_final_inliers", c.min_final_inliers, ctx);
  yaml_get(n, "snapshot_keyframes", c.snapshot_keyframes, ctx);
}

void read_merge(const YAML::Node& n, MergeConfig& c, const std::string& ctx) {
  if (!n) return;
  check_known_keys(n, {"enabled", "start_frames", "lost_frames", "world", "global_ba"}, ctx);
  yaml_get(n, "enabled", c.enabled, ctx);
  yaml_get(n, "start_frames", c.start_frames, ctx);
  yaml_get(n, "lost_frames", c.lost_frames, ctx);
  yaml_get(n, "world", c.world, ctx);
  yaml_get(n, "global_ba", c.global_ba, ctx);
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

void TrackerConfig::validate() const {
  pose.validate();
  require(close_depth_m > 0, "tracker.close_depth_m must be > 0");
  require(motion_radius_px > 0 && local_radius_factor > 0, "tracker: search radii must be > 0");
  require(min_pose_inliers >= 3 && min_local_inliers >= min_pose_inliers,
          "tracker: need 3 <= min_pose_inliers <= min_local_inliers");
  require(wide_match_ratio <= 1.0, "tracker.wide_match_ratio must be <= 1 (<= 0.7: off)");
  require(max_frames_between_keyframes >= 1 && min_frames_between_keyframes >= 0,
          "tracker: keyframe frame gaps must be >= 1 / >= 0");
  require(keyframe_ref_ratio > 0 && keyframe_ref_ratio <= 1, "tracker.keyframe_ref_ratio must be in (0, 1]");
  require(keyframe_decay_ratio >= 0 && keyframe_decay_ratio < 1,
          "tracker.keyframe_decay_ratio must be in [0, 1)");
  require(keyframe_max_deg >= 0 && keyframe_max_m >= 0,
          "tracker.keyframe_max_deg / keyframe_max_m must be >= 0");
  require(max_pending_keyframes >= 1 && min_init_depth_points >= 3, "tracker: bad pending/init limits");
  require(anchor_keyframes >= 1, "tracker.anchor_keyframes must be >= 1");
  require(
      coast_frames >= 0 && bridge_deg >= 0 && bridge_m >= 0 && bridge_min_inliers >= min_pose_inliers,
      "tracker: coast_frames, bridge_deg and bridge_m must be >= 0, bridge_min_inliers >= min_pose_inliers");
  require(odometry_frames >= 0 && odometry_deg >= 0 && odometry_m >= 0 && odometry_agree_fraction >= 0,
          "tracker: odometry_frames, odometry_deg, odometry_m and odometry_agree_fraction must be >= 0");
  require(odometry_min_colour_agreement >= -1 && odometry_min_colour_agreement <= 1,
          "tracker.odometry_min_colour_agreement must be in [-1, 1] (-1 = off)");
  odometry.validate();
}

void LoopClosingConfig::validate() const {
  loop.validate();
  reloc.validate();
}

void read_loop_closing(const YAML::Node& n, LoopClosingConfig& c, const std::string& ctx) {
  if (!n) return;
  std::vector<std::string> keys = kLoopKeys;
  keys.insert(keys.end(), {"enabled", "relocalisation", "vocabulary", "reloc", "merge"});
  check_known_keys(n, keys, ctx);
  yaml_get(n, "enabled", c.enabled, ctx);
  yaml_get(n, "relocalisation", c.relocalisation, ctx);
  yaml_get(n, "vocabulary", c.vocabulary, ctx);
  read_loop(n, c.loop, ctx);
  read_reloc(n["reloc"], c.reloc, ctx);
  read_merge(n["merge"], c.loop.merge, ctx);
}

void SlamConfig::validate() const {
  features.validate();
  tracker.validate();
  mapper.validate();
  loop_closing.validate();
  require(queue_capacity >= tracker.max_pending_keyframes + 2,
          "slam.queue_capacity must be >= tracker.max_pending_keyframes + 2 = " +
              std::to_string(tracker.max_pending_keyframes + 2) + " (got " + std::to_string(queue_capacity) +
              ")");
  require(T_c_r.matrix().allFinite(), "slam.T_c_r must be finite");
  require(mapping_lag_frames >= 0 && mapping_lag_frames <= 30,
          "slam.mapping_lag_frames must be in [0, 30] (got " + std::to_string(mapping_lag_frames) + ")");
}

SlamConfig slam_config_from_yaml(const YAML::Node& node, const std::string& ctx) {
  SlamConfig c;
  if (!node || node.IsNull()) return c;
  check_known_keys(
      node, {"features", "tracker", "mapper", "T_c_r", "threaded", "queue_capacity", "mapping_lag_frames"},
      ctx);
  read_features(node["features"], c.features, ctx);
  read_tracker(node["tracker"], c.tracker, ctx);
  read_mapper(node["mapper"], c.mapper, ctx);
  if (node["T_c_r"]) c.T_c_r = read_pose(node["T_c_r"], ctx);
  yaml_get(node, "threaded", c.threaded, ctx);
  yaml_get(node, "queue_capacity", c.queue_capacity, ctx);
  yaml_get(node, "mapping_lag_frames", c.mapping_lag_frames, ctx);
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
