#include "s3m/slam/slam_config.hpp"

#include <charconv>
#include <cmath>
#include <vector>

#include "s3m/core/config_table.hpp"
#include "s3m/core/error.hpp"
#include "s3m/core/yaml_util.hpp"

// The YAML keys of every SLAM config struct, once each (core/config_table.hpp). The tree is the
// one users know: flat tracker.coast_frames and tracker.odometry_* keys fill TrackerConfig::dead_reckoning,
// and LoopConfig's keys sit at the top of `loop_closing:` next to enabled and relocalisation.
namespace s3m::features {

void fields(config::FieldVisitor& v, OrbConfig& c) {
  v("n_features", c.n_features);
  v("scale_factor", c.scale_factor);
  v("n_levels", c.n_levels);
  v("ini_fast_threshold", c.ini_fast_threshold);
  v("min_fast_threshold", c.min_fast_threshold);
  v("cell_px", c.cell_px);
  v("parallel_levels", c.parallel_levels);
  v("level_sigma_exponent", c.level_sigma_exponent);
}

void fields(config::FieldVisitor& v, DepthNoiseConfig& c) {
  v("model", c.model);
  v("sigma0_m", c.sigma0_m);
  v("k_per_m", c.k_per_m);
}

void fields(config::FieldVisitor& v, FeatureConfig& c) {
  v("orb", c.orb);
  v("min_depth_m", c.min_depth_m);
  v("max_depth_m", c.max_depth_m);
  v("depth_discontinuity_ratio", c.depth_discontinuity_ratio);
  v("depth_window_px", c.depth_window_px);
  v("depth_noise", c.depth_noise);
}

void fields(config::FieldVisitor& v, BowMatchConfig& c) {
  v("max_hamming", c.max_hamming);
  v("ratio", c.ratio);
}

}  // namespace s3m::features

namespace s3m::slam {

void fields(config::FieldVisitor& v, TrackerConfig& c) {
  v("pose_rounds", c.pose.rounds);
  v("pose_iterations", c.pose.iterations);
  v("close_depth_m", c.close_depth_m);
  v("motion_radius_px", c.motion_radius_px);
  v("min_motion_matches", c.min_motion_matches);
  v("min_pose_inliers", c.min_pose_inliers);
  v("wide_match_ratio", c.wide_match_ratio);
  v("local_radius_factor", c.local_radius_factor);
  v("min_local_inliers", c.min_local_inliers);
  v("max_frames_between_keyframes", c.max_frames_between_keyframes);
  v("min_frames_between_keyframes", c.min_frames_between_keyframes);
  v("keyframe_ref_ratio", c.keyframe_ref_ratio);
  v("keyframe_decay_ratio", c.keyframe_decay_ratio);
  v("keyframe_max_deg", c.keyframe_max_deg);
  v("keyframe_max_m", c.keyframe_max_m);
  v("close_tracked_min", c.close_tracked_min);
  v("close_untracked_min", c.close_untracked_min);
  v("max_pending_keyframes", c.max_pending_keyframes);
  v("min_init_depth_points", c.min_init_depth_points);
  v("anchor_keyframes", c.anchor_keyframes);
  v("depth_time_compensation", c.depth_time_compensation);
  v("coast_frames", c.dead_reckoning.coast_frames);
  v("bridge_deg", c.bridge_deg);
  v("bridge_m", c.bridge_m);
  v("bridge_min_inliers", c.bridge_min_inliers);
  v("odometry_frames", c.dead_reckoning.odometry_frames);
  v("odometry_deg", c.dead_reckoning.odometry_deg);
  v("odometry_m", c.dead_reckoning.odometry_m);
  v("odometry_agree_fraction", c.dead_reckoning.odometry_agree_fraction);
  v("odometry_min_colour_agreement", c.dead_reckoning.odometry_min_colour_agreement);
  v("odometry_downsample", c.dead_reckoning.odometry.downsample);
  v("odometry_max_depth_diff_m", c.dead_reckoning.odometry.max_depth_diff_m);
  v("odometry_min_observed_ratio", c.dead_reckoning.odometry.min_observed_ratio);
  v("odometry_max_step_m", c.dead_reckoning.odometry.max_step_m);
  v("odometry_max_step_deg", c.dead_reckoning.odometry.max_step_deg);
  v("odometry_gap_max_depth_diff_m", c.dead_reckoning.odometry.gap_max_depth_diff_m);
}

void fields(config::FieldVisitor& v, BaConfig& c) {
  v("first_iterations", c.first_iterations);
  v("second_iterations", c.second_iterations);
  v("chi2_mono", c.chi2_mono);
  v("chi2_stereo", c.chi2_stereo);
  v("max_local_keyframes", c.max_local_keyframes);
  v("global_iterations", c.global_iterations);
  v("max_keyframe_step_deg", c.max_keyframe_step_deg);
  v("max_keyframe_step_m", c.max_keyframe_step_m);
}

void fields(config::FieldVisitor& v, DenseLinkConfig& c) {
  v("enabled", c.enabled);
  v("sigma_deg", c.sigma_deg);
  v("sigma_m", c.sigma_m);
  v("max_deg", c.max_deg);
  v("max_m", c.max_m);
  v("downsample", c.downsample);
  v("max_median_deg", c.max_median_deg);
  v("max_median_m", c.max_median_m);
}

void fields(config::FieldVisitor& v, MapperConfig& c) {
  v("close_depth_m", c.close_depth_m);
  v("min_new_points", c.min_new_points);
  v("min_found_ratio", c.min_found_ratio);
  v("fuse_neighbours", c.fuse_neighbours);
  v("local_ba", c.local_ba);
  v("cull_keyframes", c.cull_keyframes);
  v("redundant_ratio", c.redundant_ratio);
  v("snapshot_keyframes", c.snapshot_keyframes);
  v("final_global_ba", c.final_global_ba);
  v("dense_links", c.dense_links);
  v("ba", c.ba);
}

void fields(config::FieldVisitor& v, LoopDetectorConfig& c) {
  v("min_common_words_ratio", c.min_common_words_ratio);
  v("group_score_ratio", c.group_score_ratio);
  v("group_neighbours", c.group_neighbours);
  v("consistency", c.consistency);
}

void fields(config::FieldVisitor& v, Se3RansacConfig& c) {
  v("max_iterations", c.max_iterations);
  v("threshold_m", c.threshold_m);
  v("depth_ratio", c.depth_ratio);
  v("min_inliers", c.min_inliers);
  v("seed", c.seed);
}

void fields(config::FieldVisitor& v, PoseGraphConfig& c) {
  v("max_iterations", c.max_iterations);
  v("loop_huber", c.loop_huber);
}

void fields(config::FieldVisitor& v, PnpConfig& c) {
  v("iterations", c.iterations);
  v("reprojection_px", c.reprojection_px);
  v("confidence", c.confidence);
  v("min_inliers", c.min_inliers);
}

void fields(config::FieldVisitor& v, MergeConfig& c) {
  v("enabled", c.enabled);
  v("start_frames", c.start_frames);
  v("lost_frames", c.lost_frames);
  v("world", c.world);
  v("global_ba", c.global_ba);
}

// At the top of `loop_closing:` (LoopClosingConfig's table calls this one in place).
void fields(config::FieldVisitor& v, LoopConfig& c) {
  v("min_keyframes", c.min_keyframes);
  v("min_keyframes_since_loop", c.min_keyframes_since_loop);
  v("direct_level", c.direct_level);
  v("detector", c.detector);
  v("bow_match", c.bow_match);
  v("min_bow_matches", c.min_bow_matches);
  v("ransac", c.ransac);
  v("loop_group_size", c.loop_group_size);
  v("search_radius_factor", c.search_radius_factor);
  v("min_projection_matches", c.min_projection_matches);
  v("essential_min_weight", c.essential_min_weight);
  v("pose_graph", c.pose_graph);
  v("global_ba", c.global_ba);
  v("ba", c.ba);
  v("merge", c.merge);
}

void fields(config::FieldVisitor& v, RelocConfig& c) {
  v("max_candidates", c.max_candidates);
  v("min_score_ratio", c.min_score_ratio);
  v("bow_match", c.bow_match);
  v("min_bow_matches", c.min_bow_matches);
  v("pnp", c.pnp);
  v("local_keyframes", c.local_keyframes);
  v("wide_radius_factor", c.wide_radius_factor);
  v("search_radius_factor", c.search_radius_factor);
  v("min_final_inliers", c.min_final_inliers);
  v("snapshot_keyframes", c.snapshot_keyframes);
}

void fields(config::FieldVisitor& v, LoopClosingConfig& c) {
  v("enabled", c.enabled);
  v("relocalisation", c.relocalisation);
  v("vocabulary", c.vocabulary);
  fields(v, c.loop);
  v("reloc", c.reloc);
}

namespace {

SE3 read_pose(const YAML::Node& n, const std::string& ctx) {
  std::vector<double> t{0, 0, 0}, q{0, 0, 0, 1};
  YamlMap(n, ctx).get("t", t).get("q", q).read();
  if (t.size() != 3 || q.size() != 4)
    throw ParseError(ctx, n.Mark().line + 1, "bad T_c_r", "t: [x, y, z] and q: [qx, qy, qz, qw]");
  const Quat quat(q[3], q[0], q[1], q[2]);
  if (std::abs(quat.norm() - 1.0) > 1e-3)
    throw ParseError(ctx, n.Mark().line + 1, "T_c_r quaternion is not unit length", "a unit quaternion");
  return make_se3(Vec3(t[0], t[1], t[2]), quat);
}

bool reads_back_as(const Quat& q, const Mat3& R) {
  return std::abs(q.norm() - 1.0) < 1e-9 && make_se3(Vec3::Zero(), q).linear() == R;
}

double round_to_digits(double x, int digits) {
  char buf[32];
  const auto end = std::to_chars(buf, buf + sizeof buf, x, std::chars_format::general, digits).ptr;
  double r = x;
  std::from_chars(buf, end, r);
  return r;
}

// The quaternion to write for R: the shortest decimals, else the nearest doubles (within 2 ulps),
// that read_pose turns into exactly R again, so that a rerun from config_effective.yaml has the
// same calibration bit for bit. Quat(R) itself often does not (normalising and the product formula
// round); when nothing nearby does, it is written and the rotation reads back within ~1e-16.
Quat quaternion_of(const Mat3& R) {
  const Quat q(R);
  for (int digits = 1; digits <= 17; ++digits) {
    const Quat c(round_to_digits(q.w(), digits), round_to_digits(q.x(), digits),
                 round_to_digits(q.y(), digits), round_to_digits(q.z(), digits));
    if (reads_back_as(c, R)) return c;
  }
  for (int combo = 0; combo < 625; ++combo) {  // every component moved by -2..2 ulps
    Quat c = q;
    for (int i = 0, code = combo; i < 4; ++i, code /= 5)
      for (int step = code % 5 - 2, k = 0; k < std::abs(step); ++k)
        c.coeffs()[i] = std::nextafter(c.coeffs()[i], step > 0 ? 2.0 : -2.0);
    if (reads_back_as(c, R)) return c;
  }
  return q;
}

YAML::Node pose_node(const SE3& T) {
  const Quat q = quaternion_of(T.linear());
  YAML::Node n(YAML::NodeType::Map), t(YAML::NodeType::Sequence), r(YAML::NodeType::Sequence);
  for (int i = 0; i < 3; ++i) t.push_back(config::format_number(T.translation()[i]));
  for (const double x : {q.x(), q.y(), q.z(), q.w()}) r.push_back(config::format_number(x));
  n["t"] = t;
  n["q"] = r;
  n.SetStyle(YAML::EmitterStyle::Flow);
  return n;
}

// `T_c_r: {t: [x, y, z], q: [qx, qy, qz, qw]}` (metres, unit quaternion).
config::Custom pose_field(SE3& T) {
  return {[&T](const YAML::Node& n, const std::string&, const std::string& ctx) { T = read_pose(n, ctx); },
          [&T] { return pose_node(T); }};
}

}  // namespace

void fields(config::FieldVisitor& v, SlamConfig& c) {
  v("features", c.features);
  v("tracker", c.tracker);
  v("mapper", c.mapper);
  v("T_c_r", pose_field(c.T_c_r));
  v("threaded", c.threaded);
  v("queue_capacity", c.queue_capacity);
  v("mapping_lag_frames", c.mapping_lag_frames);
}

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
  require(bridge_deg >= 0 && bridge_m >= 0 && bridge_min_inliers >= min_pose_inliers,
          "tracker: bridge_deg and bridge_m must be >= 0, bridge_min_inliers >= min_pose_inliers");
  dead_reckoning.validate();
}

void LoopClosingConfig::validate() const {
  loop.validate();
  reloc.validate();
}

void read_loop_closing(const YAML::Node& n, LoopClosingConfig& c, const std::string& ctx) {
  if (n) config::read(n, config::table_of(c), ctx);
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
  config::read(node, config::table_of(c), ctx);
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
