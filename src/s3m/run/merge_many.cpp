// `s3m merge` of N runs (merge_many.hpp): overlap of every pair, merges along a maximum spanning
// tree of the overlap graph, one semantic map rebuilt from every merged run's kept clouds.
#include "s3m/run/merge_many.hpp"

#include <filesystem>
#include <map>
#include <optional>

#include <fmt/format.h>
#include <spdlog/spdlog.h>

#include "s3m/core/atomic_file.hpp"
#include "s3m/core/error.hpp"
#include "s3m/features/bow_vocabulary.hpp"
#include "s3m/io/output_folder.hpp"
#include "s3m/io/trajectory.hpp"
#include "s3m/pipeline/factories.hpp"
#include "s3m/pipeline/keyframe_store.hpp"
#include "s3m/pipeline/map_integrator.hpp"
#include "s3m/pipeline/session_io.hpp"
#include "s3m/run/session_merge.hpp"

namespace s3m::run {
namespace fs = std::filesystem;
using nlohmann::json;

namespace {

struct Session {
  Session(std::string d, slam::LoadedSlamMap m) : dir(std::move(d)), map(std::move(m)) {}
  std::string dir;
  slam::LoadedSlamMap map;  // in the run's own world
  pipeline::KeyframeStore clouds;
  KeyframeId offset = 0;  // its keyframe ids in the merged map are shifted by this
  int order = -1;         // position in the merge order; -1: not placed
  int joined_to = -1;     // the merged run it overlaps most (the spanning tree's edge)
  slam::SessionOverlap edge;
};

void check_run_folder(const std::string& dir, std::size_t k) {
  if (dir.empty() || !fs::is_directory(dir))
    throw Error(fmt::format("merge: run {} '{}' is not a folder (expected a folder `s3m run --out` wrote)",
                            k + 1, dir));
  if (!fs::exists(fs::path(dir) / pipeline::kKeptCloudsFile))
    throw Error(
        fmt::format("merge: run {} '{}' has no {} (a --slam-only run?): every run needs its kept clouds "
                    "to merge the semantic maps",
                    k + 1, dir, pipeline::kKeptCloudsFile));
}

void check_folders(const MergeManyOptions& o) {
  require(o.runs.size() >= 2,
          "merge: at least two runs are needed (got " + std::to_string(o.runs.size()) + ")");
  require(!o.out_dir.empty(), "merge: an output folder is required (--out)");
  std::error_code ec;
  for (std::size_t k = 0; k < o.runs.size(); ++k) {
    check_run_folder(o.runs[k], k);
    for (std::size_t j = 0; j < k; ++j)
      if (fs::equivalent(o.runs[j], o.runs[k], ec))
        throw Error(fmt::format("merge: run {} '{}' is run {} again", k + 1, o.runs[k], j + 1));
    if (fs::exists(o.out_dir) && fs::equivalent(o.out_dir, o.runs[k], ec))
      throw Error("merge: --out '" + o.out_dir + "' is one of the runs being merged (write it elsewhere)");
  }
}

std::vector<Session> load_sessions(const MergeManyOptions& o,
                                   const std::shared_ptr<const features::Vocabulary>& vocabulary) {
  const int level = o.config.slam.loop_closing.loop.direct_level;
  std::vector<Session> s;
  for (std::size_t k = 0; k < o.runs.size(); ++k) {
    const std::string path = (fs::path(o.runs[k]) / pipeline::kSlamMapFile).string();
    if (k == 0) {
      s.emplace_back(o.runs[k], slam::load_slam_map(path, vocabulary, level));
    } else {
      try {
        s.emplace_back(o.runs[k], slam::load_slam_map(path, s[0].map.camera, vocabulary, level));
      } catch (const ParseError& e) {
        throw Error(std::string(e.what()) + " ('this run' is run 1, " + o.runs[0] + ")");
      }
    }
    pipeline::load_kept_clouds((fs::path(o.runs[k]) / pipeline::kKeptCloudsFile).string(), s[k].clouds);
  }
  return s;
}

// The overlap graph: w[i][j] (i < j) is run j searched in run i.
using Overlaps = std::vector<std::vector<slam::SessionOverlap>>;

Overlaps overlaps(const std::vector<Session>& s,
                  const std::shared_ptr<const features::Vocabulary>& vocabulary, const MergeManyOptions& o) {
  Overlaps w(s.size(), std::vector<slam::SessionOverlap>(s.size()));
  for (std::size_t i = 0; i < s.size(); ++i)
    for (std::size_t j = i + 1; j < s.size(); ++j) {
      w[i][j] = slam::find_session_overlap(s[i].map, s[j].map, vocabulary, o.config.slam.loop_closing.loop,
                                           o.search);
      w[j][i] = w[i][j];
      spdlog::info("merge: runs {} and {}: {} verified pairs, {} agreeing{}", i + 1, j + 1,
                   w[i][j].n_verified, w[i][j].n_agreeing, w[i][j].placed ? "" : " (no alignment)");
    }
  return w;
}

// Stronger overlap: more agreeing verified pairs, then more verified pairs, then more matches.
bool stronger(const slam::SessionOverlap& a, const slam::SessionOverlap& b) {
  if (!a.placed) return false;
  if (!b.placed) return true;
  return std::tie(a.n_agreeing, a.n_verified, a.n_matches) >
         std::tie(b.n_agreeing, b.n_verified, b.n_matches);
}

// The merge order: the strongest pair first (its earlier run the world), then, one at a time, the
// unmerged run with the strongest overlap to a merged one (ties: the earlier listed).
std::vector<int> merge_order(std::vector<Session>& s, const Overlaps& w) {
  const int n = int(s.size());
  int first = 0;
  slam::SessionOverlap best;
  for (int i = 0; i < n; ++i)
    for (int j = i + 1; j < n; ++j)
      if (stronger(w[i][j], best)) best = w[i][j], first = i;
  std::vector<int> order{first};
  s[first].order = 0;
  for (;;) {
    int next = -1, via = -1;
    for (int j = 0; j < n; ++j) {
      if (s[j].order >= 0) continue;
      for (int i : order)
        if (stronger(w[i][j], next < 0 ? slam::SessionOverlap{} : w[via][next])) next = j, via = i;
    }
    if (next < 0) return order;
    s[next].order = int(order.size());
    s[next].joined_to = via;
    s[next].edge = w[via][next];
    order.push_back(next);
  }
}

// Merges the runs in order into the first; a run the merged map does not recognise after all is
// left out (not placed). Returns the merged map with every merged run's offset set.
slam::LoadedSlamMap merge_in_order(std::vector<Session>& s, std::vector<int>& order,
                                   const std::shared_ptr<const features::Vocabulary>& vocabulary,
                                   const MergeManyOptions& o, json& merges) {
  slam::LoadedSlamMap merged = s[order[0]].map;
  for (std::size_t k = 1; k < order.size();) {
    Session& run = s[order[k]];
    try {
      slam::MergedSessions m =
          slam::merge_sessions(merged, run.map, vocabulary, o.config.slam.loop_closing.loop, o.search);
      run.offset = m.b_offset;
      merges.push_back({{"run", order[k] + 1},
                        {"projection_matches", m.n_matches},
                        {"verified_pairs", m.n_verified},
                        {"agreeing_pairs", m.n_agreeing},
                        {"fused_points", m.correction.n_fused}});
      merged = {std::move(m.map), std::move(m.index), std::move(m.loop_edges), merged.camera};
      ++k;
    } catch (const Error& e) {
      spdlog::warn("merge: run {} not placed after all: {}", order[k] + 1, e.what());
      run.order = -1;
      order.erase(order.begin() + long(k));
    }
  }
  return merged;
}

// Every merged run's clouds in one store (ids shifted, one session number per run in merge order),
// anchored at the merged keyframe poses.
pipeline::KeyframeStore merged_store(const std::vector<Session>& s, const std::vector<int>& order,
                                     const slam::Map& map) {
  pipeline::KeyframeStore store;
  for (int k : order)
    for (const auto& [id, T] : s[k].clouds.keyframes()) store.note_keyframe(id + s[k].offset, T);
  for (int k : order)
    for (pipeline::KeptCloud c : s[k].clouds.clouds()) {
      c.anchor.keyframe += s[k].offset;
      c.session = s[k].order;
      store.add_kept(std::move(c));
    }
  std::map<KeyframeId, SE3> poses;
  for (const auto& [id, T] : store.keyframes())
    if (map.has_keyframe(id) || map.culled().count(id)) poses.emplace(id, map.resolve_T_w_kf(id));
  store.update_poses(poses);
  return store;
}

// A run's trajectory in the merged world: each frame moves as its run's keyframe nearest in time
// moved (merged pose times its own pose's inverse). Empty without a trajectory file.
io::Trajectory re_expressed(const Session& run, const slam::Map& merged) {
  const fs::path path = fs::path(run.dir) / "trajectory_camera.txt";
  if (!fs::exists(path)) return {};
  std::map<double, SE3> correction_at;
  for (const auto& [id, kf] : run.map.map.keyframes())
    if (merged.has_keyframe(id + run.offset))
      correction_at[kf.t_s] = merged.keyframe(id + run.offset).T_w_c * kf.T_w_c.inverse();
  return corrected_trajectory(path.string(), correction_at);
}

// An unplaced run's session, copied as it is.
void keep_unplaced(const Session& run, int k, const fs::path& out) {
  const fs::path dir = out / "unplaced" / std::to_string(k + 1);
  fs::create_directories(dir);
  for (const char* f : {pipeline::kSlamMapFile, pipeline::kKeptCloudsFile, "map.ot", "map.ply",
                        "trajectory_camera.txt", "keyframes.txt", "metrics.json"}) {
    const fs::path from = fs::path(run.dir) / f;
    if (fs::exists(from)) fs::copy_file(from, dir / f, fs::copy_options::overwrite_existing);
  }
}

json overlap_json(const Overlaps& w) {
  json rows = json::array();
  for (std::size_t i = 0; i < w.size(); ++i)
    for (std::size_t j = i + 1; j < w.size(); ++j)
      rows.push_back({{"runs", {i + 1, j + 1}},
                      {"placed", w[i][j].placed},
                      {"verified_pairs", w[i][j].n_verified},
                      {"agreeing_pairs", w[i][j].n_agreeing},
                      {"projection_matches", w[i][j].n_matches}});
  return rows;
}

}  // namespace

json merge_many(const MergeManyOptions& o) {
  o.config.validate();
  check_folders(o);
  // 1. Every run's SLAM map (checked against run 1's camera) and kept clouds.
  const auto vocabulary = pipeline::load_vocabulary(o.config.slam.loop_closing);
  std::vector<Session> s = load_sessions(o, vocabulary);
  // 2. The overlap of every pair, the merge order, the merges.
  const Overlaps w = overlaps(s, vocabulary, o);
  std::vector<int> order = merge_order(s, w);
  json merges = json::array();
  const slam::LoadedSlamMap merged = merge_in_order(s, order, vocabulary, o, merges);
  for (std::size_t k = 0; k < order.size(); ++k)
    s[order[k]].order = int(k);  // a run left out shifts the rest
  // 3. The semantic map from every merged run's clouds at the merged poses.
  const pipeline::KeyframeStore store = merged_store(s, order, merged.map);
  pipeline::MapIntegrator semantic(o.config.map);
  semantic.rebuild(store);

  // 4. Outputs (staged: a merge that fails halfway leaves the folder as it was): the merged session,
  // each merged run's trajectory, the unplaced runs as they are.
  io::StagedFolder staged(o.out_dir, "--out");
  const fs::path out(staged.path());
  slam::save_slam_map((out / pipeline::kSlamMapFile).string(), merged.map, merged.index, merged.loop_edges,
                      merged.camera);
  pipeline::save_kept_clouds((out / pipeline::kKeptCloudsFile).string(), store);
  semantic.save((out / "map.ot").string(), (out / "map.ply").string());
  io::Trajectory keyframes;
  for (const auto& [id, kf] : merged.map.keyframes()) keyframes.push_back({kf.t_s, kf.T_w_c});
  io::write_tum_trajectory((out / "keyframes.txt").string(), keyframes);
  json runs = json::array();
  for (std::size_t k = 0; k < s.size(); ++k) {
    const Session& run = s[k];
    json r = {{"run", k + 1},
              {"dir", run.dir},
              {"keyframes", run.map.map.n_keyframes()},
              {"kept_clouds", run.clouds.size()}};
    if (run.order < 0) {
      r["status"] = "not placed";
      keep_unplaced(run, int(k), out);
      r["kept_as"] = (fs::path(o.out_dir) / "unplaced" / std::to_string(k + 1)).string();
    } else {
      r["status"] = run.order == 0 ? "world" : "joined";
      r["order"] = run.order + 1;
      r["keyframe_id_offset"] = run.offset;
      if (run.order > 0)
        r["joined_to"] = run.joined_to + 1, r["verified_pairs"] = run.edge.n_verified,
        r["agreeing_pairs"] = run.edge.n_agreeing;
      const io::Trajectory t = re_expressed(run, merged.map);
      const std::string name = fmt::format("trajectory_camera_{}.txt", k + 1);
      if (!t.empty()) io::write_tum_trajectory((out / name).string(), t), r["trajectory"] = name;
    }
    runs.push_back(r);
  }
  json j = {{"world", order[0] + 1}, {"order", json::array()},      {"runs", runs},
            {"merges", merges},      {"overlaps", overlap_json(w)}, {"map", semantic.describe()}};
  for (int k : order) j["order"].push_back(k + 1);
  write_text_atomic((out / "merge.json").string(), j.dump(2) + "\n");
  staged.commit(merge_output_names(o.out_dir));
  return j;
}

}  // namespace s3m::run
