// The merge stage and the batch summary (summary.hpp).
#include "s3m/batch/summary.hpp"

#include <cmath>
#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>

#include <spdlog/spdlog.h>

#include "s3m/batch/plan.hpp"
#include "s3m/core/atomic_file.hpp"
#include "s3m/core/error.hpp"
#include "s3m/io/gt_voxels.hpp"
#include "s3m/io/trajectory.hpp"
#include "s3m/mapping/map_io.hpp"
#include "s3m/run/evaluation.hpp"
#include "s3m/run/merge_many.hpp"

namespace s3m::batch {
namespace fs = std::filesystem;
using nlohmann::json;

namespace {

json read_json(const std::string& path) {
  std::ifstream in(path);
  if (!in) return json::object();
  try {
    return json::parse(in);
  } catch (const json::exception&) {
    return json::object();
  }
}

std::string read_bytes(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

json run_json(const Paths& paths, const Recording& r) {
  const RunStatus st = read_status(paths, r);
  json j = {{"name", r.name}, {"path", r.path}, {"status", to_string(st.state)}, {"log", paths.log(r)}};
  if (st.state != RunState::kDone) {
    if (!st.error.empty()) j["error"] = st.error;
    if (st.exit_code >= 0) j["exit_code"] = st.exit_code;
    return j;
  }
  j["run"] = paths.run(r);
  const json m = read_json(paths.run(r) + "/metrics.json");
  j["frames"] = m.value("frames", 0);
  j["frames_total"] = m.value("frames_total", 0);
  j["keyframes"] = m.value("keyframes", 0);
  if (m.contains("trajectory") && m["trajectory"].contains("ate_rmse_m"))
    j["ate_rmse_m"] = m["trajectory"]["ate_rmse_m"];
  if (m.contains("map")) {
    const json& map = m["map"];
    j["map"] = {{"voxels", map.value("voxels", 0)}, {"file_bytes", map.value("file_bytes", 0)}};
    if (map.contains("miou")) j["map"]["miou"] = map["miou"];
  }
  if (m.contains("inputs")) j["dataset"] = m["inputs"].value("dataset", "");
  if (m.contains("map") && m["map"].contains("gt_voxel_map")) j["gt_voxel_map"] = m["map"]["gt_voxel_map"];
  return j;
}

// The merged map against the world run's ground truth (its alignment: the merged map is in its
// world). The runs of the same building (the same ground-truth voxels; each at its own alignment)
// give the voxels to judge on: the union of what they observed, and each run's own. The merged
// map's mIoU on that union is its headline (every run's is there too), and on each run's own
// voxels it stands against that run's own map. Scored on the merged map's own observed space
// (run::score_map, as a run scores itself) it also counts the fringe its seams shift into view.
void evaluate_merged(json& merged, json& runs) {
  const json& world = runs.at(merged.at("world_index").get<std::size_t>());
  if (!world.contains("gt_voxel_map") || !world.contains("dataset")) return;
  const std::string gt = world["gt_voxel_map"];
  const auto T_world = T_run_gt(world["run"], world["dataset"]);
  if (!T_world) return;
  const std::string map_ot = merged.at("dir").get<std::string>() + "/map.ot";
  json& map = merged["map"];
  const std::string gt_bytes = read_bytes(gt);
  std::map<std::size_t, std::set<std::size_t>> own;  // run index -> the voxels it observed
  std::set<std::size_t> seen;
  for (const std::size_t k : merged.at("placed_indices").get<std::vector<std::size_t>>()) {
    json& r = runs.at(k);
    if (!r.contains("gt_voxel_map") || read_bytes(r["gt_voxel_map"]) != gt_bytes) continue;
    const auto T = T_run_gt(r["run"], r["dataset"]);
    if (!T) continue;
    const std::string run_ot = r["run"].get<std::string>() + "/map.ot";
    own[k] = observed_gt_voxels(run_ot, gt, *T);
    seen.insert(own[k].begin(), own[k].end());
    r["map"]["observed_gt_voxels"] = own[k].size();
    r["map"]["miou_on_own"] = miou_on(run_ot, gt, *T, own[k]);
    r["map"]["merged_miou_on_own"] = miou_on(map_ot, gt, *T_world, own[k]);
  }
  for (const auto& [k, voxels] : own) {
    const auto T = T_run_gt(runs[k]["run"], runs[k]["dataset"]);
    runs[k]["map"]["miou_on_union"] = miou_on(runs[k]["run"].get<std::string>() + "/map.ot", gt, *T, seen);
  }
  map["union_observed_gt_voxels"] = seen.size();
  map["coverage_of_union"] =
      seen.empty() ? 0.0 : double(known_near(map_ot, gt, *T_world, seen)) / double(seen.size());
  map["miou"] = miou_on(map_ot, gt, *T_world, seen);
  map["miou_own_observed"] = run::score_map(*mapping::load_semantic_map(map_ot), gt, *T_world).miou;
}

// The N-way merge of the runs that succeeded, or the one already in DIR/merged/ when it merged
// exactly those runs.
json merge_runs(const Manifest& m, const Paths& paths, const json& runs) {
  std::vector<std::string> dirs;
  std::vector<std::size_t> index;
  for (std::size_t k = 0; k < runs.size(); ++k)
    if (runs[k]["status"] == "done") dirs.push_back(runs[k]["run"]), index.push_back(k);
  json merged = {{"dir", paths.merged()}};
  if (dirs.size() < 2) {
    merged["status"] = "not merged";
    merged["error"] = "fewer than two runs succeeded";
    return merged;
  }
  // The runs by folder name (runs/<name>): DIR may have been moved since.
  json j = read_json(paths.merged() + "/merge.json");
  std::vector<std::string> before, now;
  for (const auto& r : j.value("runs", json::array()))
    before.push_back(fs::path(r.value("dir", "")).filename());
  for (const auto& d : dirs) now.push_back(fs::path(d).filename());
  if (before != now || !fs::exists(paths.merged() + "/map.ot")) {
    fs::remove_all(paths.merged());
    run::MergeManyOptions o;
    o.runs = dirs;
    o.out_dir = paths.merged();
    o.config =
        m.merge_config.empty() ? pipeline::PipelineConfig{} : pipeline::load_pipeline_config(m.merge_config);
    try {
      j = run::merge_many(o);
    } catch (const Error& e) {
      merged["status"] = "failed";
      merged["error"] = e.what();
      return merged;
    }
  } else {
    spdlog::info("batch: {} already merges the runs that succeeded", paths.merged());
  }
  merged["status"] = "merged";
  merged["world_index"] = index.at(j["world"].get<std::size_t>() - 1);
  merged["order"] = json::array();
  for (const auto& k : j["order"])
    merged["order"].push_back(runs[index.at(k.get<std::size_t>() - 1)]["name"]);
  merged["placed_indices"] = json::array();
  merged["runs"] = json::array();
  for (const auto& r : j["runs"]) {
    const std::size_t k = index.at(r["run"].get<std::size_t>() - 1);
    json e = {{"name", runs[k]["name"]}, {"status", r["status"]}};
    if (r.contains("joined_to"))
      e["joined_to"] = runs[index.at(r["joined_to"].get<std::size_t>() - 1)]["name"];
    for (const char* key : {"verified_pairs", "agreeing_pairs", "kept_as"})
      if (r.contains(key)) e[key] = r[key];
    if (r["status"] != "not placed") merged["placed_indices"].push_back(k);
    merged["runs"].push_back(e);
  }
  merged["map"] = {{"voxels", j["map"].value("voxels", 0)}};
  return merged;
}

}  // namespace

json merge_stage(const std::string& manifest, const std::string& dir) {
  const Manifest m = load_manifest(manifest);
  Paths paths;
  paths.dir = fs::canonical(dir).string();
  json runs = json::array();
  for (const Recording& r : m.recordings) runs.push_back(run_json(paths, r));
  json merged = merge_runs(m, paths, runs);
  if (merged["status"] == "merged") evaluate_merged(merged, runs);
  merged.erase("placed_indices");
  if (merged.contains("world_index"))
    merged["world"] = runs[merged["world_index"].get<std::size_t>()]["name"];
  merged.erase("world_index");
  int failed = 0;
  for (const auto& r : runs) failed += r["status"] != "done";
  json summary = {{"manifest", m.file}, {"dir", paths.dir}, {"recordings", runs.size()},
                  {"failed", failed},   {"runs", runs},     {"merged", merged}};
  write_text_atomic(paths.dir + "/summary.json", summary.dump(2) + "\n");
  write_text_atomic(paths.dir + "/summary.html", summary_html(summary));
  return summary;
}

}  // namespace s3m::batch
