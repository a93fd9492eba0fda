#include "s3m/run/metrics.hpp"

#include <algorithm>
#include <filesystem>

#include "s3m/core/classes.hpp"
#include "s3m/io/atomic_file.hpp"
#include "s3m/mapping/metrics.hpp"
#include "s3m/mapping/queries.hpp"
#include "s3m/pipeline/reprojection.hpp"
#include "s3m/run/evaluation.hpp"

namespace s3m::run {
namespace fs = std::filesystem;
using nlohmann::json;

namespace {

json timings_json(const pipeline::StageTimings& t) {
  json j = json::object();
  for (const auto& [stage, s] : t.summary())
    j[stage] = {
        {"mean", s.mean_ms}, {"p50", s.p50_ms}, {"p95", s.p95_ms}, {"max", s.max_ms}, {"count", s.count}};
  return j;
}

json per_class_json(const std::map<ClassId, double>& iou) {
  json j = json::object();
  const ClassList& classes = indoor_classes();
  for (const auto& [id, v] : iou) j[id < classes.size() ? classes.at(id).name : std::to_string(id)] = v;
  return j;
}

json classes_json() {
  json j = json::array();
  for (const auto& c : indoor_classes().all())
    j.push_back({{"id", c.id}, {"name", c.name}, {"rgb", {c.r, c.g, c.b}}});
  return j;
}

json segmentation_json(const pipeline::Pipeline& p) {
  const semantics::SegMetrics m = p.confusion().metrics();
  if (m.evaluated_px == 0) return json::object();
  std::map<ClassId, double> iou;
  for (ClassId c : m.evaluated) iou[c] = m.iou[c];
  return {{"miou", m.miou},
          {"pixel_accuracy", m.pixel_accuracy},
          {"per_class_iou", per_class_json(iou)},
          {"frames", p.counters().segmented},
          {"note", "argmax of each segmented frame vs the dataset's label image; unknown (0) not evaluated"}};
}

json iou_pair_json(const semantics::ConfusionMatrix& map, const semantics::ConfusionMatrix& frame) {
  const semantics::SegMetrics m = map.metrics(), f = frame.metrics();
  json per_class = json::object();
  const ClassList& classes = indoor_classes();
  for (ClassId c : f.evaluated) per_class[classes.at(c).name] = {{"map", m.iou[c]}, {"frame", f.iou[c]}};
  return {{"miou", m.miou},
          {"frame_miou", f.miou},
          {"pixel_accuracy", m.pixel_accuracy},
          {"frame_pixel_accuracy", f.pixel_accuracy},
          {"per_class_iou", per_class}};
}

// The final map's labels projected into the kept frames (reprojection.hpp), with the final poses.
json reprojection_json(const pipeline::Pipeline& p, const pipeline::FrameSource& source,
                       const pipeline::PipelineConfig& config) {
  const pipeline::MapIntegrator* map = p.map();
  if (!map || p.eval_frames().empty()) return json::object();
  std::map<double, SE3> T_w_c_by_t;
  for (const auto& s : p.poses().camera_trajectory()) T_w_c_by_t.emplace(s.t_s, s.T_w_x);
  pipeline::ReprojectionScore score;
  const pipeline::ReprojectionOptions opt{config.cloud.min_depth_m, config.cloud.max_depth_m, 2};
  for (const pipeline::EvalFrame& e : p.eval_frames()) {
    const auto pose = T_w_c_by_t.find(e.t_s);
    if (pose == T_w_c_by_t.end()) continue;  // not in the final trajectory (lost)
    const RgbdFrame f = source.load(static_cast<std::size_t>(e.index));
    pipeline::add_reprojection(map->tree(), source.camera(), {f.depth_m, f.labels, e.argmax, pose->second},
                               opt, score);
  }
  if (score.covered_px == 0) return json::object();
  json j = iou_pair_json(score.map, score.frame);
  j["frames"] = score.frames;
  j["coverage"] = score.coverage();
  j["note"] =
      "final map's labels projected into kept segmented frames (final poses, frame depth) vs their "
      "ground-truth labels; frame_* = the single-frame segmentation on exactly the same pixels";
  return j;
}

// Occupied, labelled voxels per top label, most frequent first: what the map says the scene is.
json class_voxels_json(const mapping::SemanticOcTree& tree) {
  const std::vector<std::size_t> n = mapping::class_voxel_counts(tree);
  std::size_t total = 0;
  for (std::size_t c : n) total += c;
  std::vector<ClassId> ids;
  for (ClassId id = 0; id < n.size(); ++id)
    if (n[id] > 0) ids.push_back(id);
  std::stable_sort(ids.begin(), ids.end(), [&](ClassId a, ClassId b) { return n[a] > n[b]; });
  const ClassList& classes = indoor_classes();
  json j = json::array();
  for (ClassId id : ids)
    j.push_back({{"class", id < classes.size() ? classes.at(id).name : std::to_string(id)},
                 {"voxels", n[id]},
                 {"share", double(n[id]) / double(total)}});
  return j;
}

// T_map_gt: the ground-truth world in the map's frame (pose alignment of the trajectory).
json map_json(const pipeline::Pipeline& p, const pipeline::OutputPaths& paths, const std::string& dataset_dir,
              const SE3& T_map_gt) {
  const pipeline::MapIntegrator* map = p.map();
  if (!map) return json::object();
  const pipeline::PipelineCounters& c = p.counters();
  json j = map->describe();
  j["class_voxels"] = class_voxels_json(map->tree());
  j["kept_clouds"] = p.keyframe_store().size();
  j["kept_clouds_mb"] = p.keyframe_store().bytes() / 1e6;
  j["kept_clouds_dropped"] = p.keyframe_store().dropped();  // over cloud.kept_clouds_budget_mb
  j["inserted_points"] = c.inserted_points;
  j["rebuilds"] = c.rebuilds;
  // Raw cloud = every in-range depth pixel of the integrated frames, with colour and k labels.
  const mapping::MapSize size = mapping::map_size(map->tree(), c.raw_points, map->tree().fusionConfig().k);
  j["raw_cloud_points"] = size.raw_points;
  j["raw_cloud_bytes"] = size.raw_cloud_bytes;
  j["memory_bytes"] = size.memory_bytes;
  j["file_bytes"] =
      !paths.map_ot.empty() && fs::exists(paths.map_ot) ? fs::file_size(paths.map_ot) : size.file_bytes;
  j["raw_over_file_ratio"] =
      j["file_bytes"].get<std::size_t>() > 0
          ? static_cast<double>(size.raw_cloud_bytes) / j["file_bytes"].get<std::size_t>()
          : 0.0;
  if (const std::string gt = find_gt_voxel_map(dataset_dir); !gt.empty()) {
    const MapScore s = score_map(*map, gt, T_map_gt);
    j["gt_voxel_map"] = gt;
    j["miou"] = s.miou;
    j["per_class_iou"] = per_class_json(s.per_class_iou);
    j["miou_with_predicted_only_classes"] = s.observed.miou;
    j["label_accuracy"] = s.observed.label_accuracy;
    j["precision"] = s.observed.precision;
    j["recall_observed"] = s.observed.recall;
    j["gt_voxels_observed"] = s.gt_observed;
    j["gt_voxels"] = s.gt_total;
    j["recall_all"] = s.all.recall;
    j["miou_all_gt"] = s.all.miou;
    j["note"] =
        "mapping::evaluate_map (1-voxel tolerance) over ground-truth voxels in observed space, "
        "mIoU over the classes of that ground truth (as the per-frame mIoU); "
        "*_all: over the whole ground-truth scene, unseen parts included";
  }
  return j;
}

// Every state's frame count, and which frames were LOST (as [first, last] index ranges) or
// RELOCALISED: LOST frames are neither in the trajectory files nor in the map.
// What SLAM learnt about the depth sensor next to the model it was configured with.
json depth_noise_json(const features::DepthNoiseEstimate& e, const features::DepthNoiseConfig& configured) {
  json bins = json::array();
  for (const auto& b : e.bins) bins.push_back({{"z_m", b.z_m}, {"n", b.n}, {"sigma_m", b.sigma_m}});
  json j = {
      {"samples", e.samples},
      {"what",
       "z measured - z of the tracked map point, robust sigma per depth bin: the sensor's noise "
       "plus the map point's own error"},
      {"bins", bins},
      {"configured",
       {{"model", configured.model}, {"sigma0_m", configured.sigma0_m}, {"k_per_m", configured.k_per_m}}},
      {"colour_depth_offset",
       {{"frames", e.offset_frames}, {"median_s", e.offset_median_s}, {"max_abs_s", e.offset_max_abs_s}}}};
  if (e.fitted) j["fit"] = {{"sigma0_m", e.sigma0_m}, {"k_per_m", e.k_per_m}};
  return j;
}

json tracking_json(const std::vector<pipeline::FrameOutcome>& frames) {
  json states = json::object(), lost = json::array(), relocalised = json::array();
  for (std::size_t i = 0; i < frames.size(); ++i) {
    const pipeline::FrameOutcome& f = frames[i];
    const char* name = to_string(f.state);
    states[name] = states.value(name, 0) + 1;
    if (f.state == FrameState::kRelocalised) relocalised.push_back(f.index);
    if (f.state != FrameState::kLost) continue;
    if (i > 0 && frames[i - 1].state == FrameState::kLost && !lost.empty())
      lost.back()[1] = f.index;
    else
      lost.push_back({f.index, f.index});
  }
  return {{"states", states}, {"lost_frames", lost}, {"relocalised_frames", relocalised}};
}

}  // namespace

std::string find_gt_voxel_map(const std::string& dataset_dir) {
  if (dataset_dir.empty()) return "";
  for (const char* name : {"gt_voxels.txt", "groundtruth_voxels.txt", "gt_voxel_map.txt"}) {
    const fs::path p = fs::path(dataset_dir) / name;
    if (fs::exists(p)) return p.string();
  }
  return "";
}

json compute_metrics(const pipeline::Pipeline& p, const pipeline::FrameSource& source,
                     const pipeline::PipelineConfig& config, const RunInfo& info,
                     const pipeline::OutputPaths& paths) {
  const pipeline::PipelineCounters& c = p.counters();
  json m;
  m["inputs"] = {{"dataset", info.dataset_dir},
                 {"config", info.config_file.empty() ? "(built-in defaults)" : info.config_file},
                 {"poses", info.poses},
                 {"segmenter", info.segmenter},
                 {"segmenter_reason", info.segmenter_reason},
                 {"mode", config.threads.deterministic ? "deterministic (1 thread)" : "threaded"}};
  m["frames"] = c.frames;
  m["frames_total"] = info.frames_total;
  m["interrupted"] = info.interrupted;
  m["skipped_frames"] = json::array();
  for (const SkippedFrame& s : info.skipped)
    m["skipped_frames"].push_back({{"index", s.index}, {"error", s.error}});
  if (!info.stopped_by.empty()) m["stopped_by"] = info.stopped_by;
  m["tracked"] = c.tracked;
  m["keyframes"] = c.keyframes;
  m["integrated"] = c.integrated;
  m["segmented"] = c.segmented;
  m["corrections"] = c.corrections;
  m["wall_time_s"] = info.wall_time_s;
  m["fps"] = info.wall_time_s > 0 ? c.frames / info.wall_time_s : 0.0;
  m["tracking"] = tracking_json(p.frames());
  const pipeline::SessionMap* session = p.poses().session_map();
  const pipeline::SessionMap::Submaps sub = session ? session->submaps() : pipeline::SessionMap::Submaps{};
  m["tracking"]["submaps"] = {{"started", sub.started},
                              {"merges", sub.merges},
                              {"keyframes_outside_world", sub.keyframes_outside_world},
                              {"frames_outside_world", sub.frames_outside_world},
                              {"world_moved", sub.world_moved}};
  if (session)
    m["tracking"]["depth_noise"] = depth_noise_json(session->depth_noise(), config.slam.features.depth_noise);
  // Calibration, not learnt: shown because it changes what tracking does with every keypoint.
  m["tracking"]["rolling_shutter_s"] = source.camera().rolling_shutter_s;
  m["timings_ms"] = timings_json(p.timings());
  const TrajectoryScore traj = evaluate_trajectory(p, source, config, paths);
  m["trajectory"] = traj.json;
  m["segmentation"] = segmentation_json(p);
  // The map lives in the estimate's world (identity for --poses gt).
  const SE3 T_map_gt = traj.T_est_gt.value_or(SE3::Identity());
  m["map"] = map_json(p, paths, source.eval_dir(), T_map_gt);
  if (json r = reprojection_json(p, source, config); !r.empty()) m["map"]["reprojected"] = r;
  m["classes"] = classes_json();
  m["outputs"] = outputs_json(paths);
  if (!info.depth_registration.empty()) m["inputs"]["depth_registration"] = info.depth_registration;
  if (!info.overlays.empty()) m["inputs"]["overlays"] = info.overlays;
  if (info.depth_median_m > 0) m["inputs"]["depth_median_m"] = info.depth_median_m;
  if (!info.depth_scale_warning.empty()) m["inputs"]["depth_scale_warning"] = info.depth_scale_warning;
  if (!info.loaded_map.empty())
    m["inputs"]["map"] = {{"folder", info.loaded_map}, {"localize_only", info.localize_only}};
  return m;
}

json outputs_json(const pipeline::OutputPaths& paths) {
  return {{"trajectory_camera", paths.trajectory_camera},
          {"trajectory_robot", paths.trajectory_robot},
          {"keyframes", paths.keyframes},
          {"frames", paths.frames},
          {"map_ot", paths.map_ot},
          {"map_ply", paths.map_ply},
          {"slam_map", paths.slam_map},
          {"kept_clouds", paths.kept_clouds},
          {"config_effective", paths.config_effective}};
}

void write_metrics(const json& metrics, const pipeline::OutputPaths& paths) {
  io::write_text_atomic(paths.metrics, metrics.dump(2) + "\n");
}

}  // namespace s3m::run
