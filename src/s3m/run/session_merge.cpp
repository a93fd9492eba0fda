// `s3m merge` (session_merge.hpp): load two saved sessions, merge the SLAM maps, rebuild the
// semantic map from both runs' kept clouds, write the merged session.
#include "s3m/run/session_merge.hpp"

#include <cmath>
#include <filesystem>

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

namespace s3m::run {
namespace fs = std::filesystem;
using nlohmann::json;

namespace {

struct RunFiles {
  std::string dir, slam_map, kept_clouds, trajectory;
};

RunFiles run_files(const std::string& dir, const char* which) {
  const fs::path d(dir);
  if (dir.empty() || !fs::is_directory(d))
    throw Error(fmt::format(
        "merge: {} '{}' is not a folder (expected a folder `s3m run --out` wrote, holding {} and {})", which,
        dir, pipeline::kSlamMapFile, pipeline::kKeptCloudsFile));
  RunFiles f{dir, (d / pipeline::kSlamMapFile).string(), (d / pipeline::kKeptCloudsFile).string(),
             (d / "trajectory_camera.txt").string()};
  if (fs::exists(f.slam_map) && !fs::exists(f.kept_clouds))
    throw Error(
        fmt::format("merge: {} has {} but no {} (a --slam-only run?): both runs need their kept clouds to "
                    "merge the semantic maps",
                    dir, pipeline::kSlamMapFile, pipeline::kKeptCloudsFile));
  return f;  // a missing slam_map.bin is reported by its loader, naming the file
}

void require_other_folder(const std::string& out, const std::string& run) {
  std::error_code ec;
  if (fs::exists(out) && fs::equivalent(out, run, ec))
    throw Error("merge: --out '" + out +
                "' is one of the runs being merged (write the merged session elsewhere)");
}

pipeline::KeyframeStore load_store(const std::string& path) {
  pipeline::KeyframeStore s;  // unlimited: a merge keeps every cloud either run kept
  pipeline::load_kept_clouds(path, s);
  return s;
}

// Both runs' clouds in one store (B's keyframe ids shifted), anchors at the merged keyframe poses.
pipeline::KeyframeStore merged_store(const pipeline::KeyframeStore& a, const pipeline::KeyframeStore& b,
                                     KeyframeId b_offset, const slam::Map& map) {
  pipeline::KeyframeStore s;
  for (const auto& [id, T] : a.keyframes()) s.note_keyframe(id, T);
  for (const auto& [id, T] : b.keyframes()) s.note_keyframe(id + b_offset, T);
  for (const pipeline::KeptCloud& c : a.clouds()) s.add_kept(c);
  for (pipeline::KeptCloud c : b.clouds()) {
    c.anchor.keyframe += b_offset;
    c.session = 1;  // whatever sessions B merged earlier, it is one session here, as A is
    s.add_kept(std::move(c));
  }
  std::map<KeyframeId, SE3> poses;
  for (const auto& [id, T] : s.keyframes())
    if (map.has_keyframe(id) || map.culled().count(id)) poses.emplace(id, map.resolve_T_w_kf(id));
  s.update_poses(poses);
  return s;
}

// A run's trajectory in the merged world: each frame moves with the keyframe of that run (ids in
// [lo, hi)) nearest to it in time. Empty when the run has no trajectory file.
io::Trajectory re_expressed(const std::string& path, const slam::Map& map, const slam::LoopCorrection& c,
                            KeyframeId lo, KeyframeId hi) {
  if (!fs::exists(path)) return {};
  std::map<double, SE3> correction_at;
  for (const auto& [id, kf] : map.keyframes())
    if (id >= lo && id < hi && c.T_w_kf_before.count(id) && c.T_w_kf_after.count(id))
      correction_at[kf.t_s] = c.T_w_kf_after.at(id) * c.T_w_kf_before.at(id).inverse();
  return corrected_trajectory(path, correction_at);
}

json pose_json(const SE3& T) {
  const Quat q(T.linear());
  const Vec3 t = T.translation();
  return {{"t", {t.x(), t.y(), t.z()}}, {"q", {q.x(), q.y(), q.z(), q.w()}}};
}

}  // namespace

json merge_runs(const MergeRunsOptions& o) {
  o.config.validate();
  require(!o.out_dir.empty(), "merge: an output folder is required (--out)");
  const RunFiles a = run_files(o.run_a, "RUN_A"), b = run_files(o.run_b, "RUN_B");
  require_other_folder(o.out_dir, o.run_a);
  require_other_folder(o.out_dir, o.run_b);
  // 1. Both SLAM maps, B checked against A's camera and both against the vocabulary.
  const auto vocabulary = pipeline::load_vocabulary(o.config.slam.loop_closing);
  const int level = o.config.slam.loop_closing.loop.direct_level;
  slam::LoadedSlamMap map_a = slam::load_slam_map(a.slam_map, vocabulary, level);
  const PinholeCamera camera = map_a.camera;
  slam::LoadedSlamMap map_b = [&] {
    try {
      return slam::load_slam_map(b.slam_map, camera, vocabulary, level);
    } catch (const ParseError& e) {
      throw Error(std::string(e.what()) + " ('this run' is RUN_A, " + a.slam_map + ")");
    }
  }();
  const pipeline::KeyframeStore clouds_a = load_store(a.kept_clouds), clouds_b = load_store(b.kept_clouds);
  const int n_a = map_a.map.n_keyframes(), n_b = map_b.map.n_keyframes();
  spdlog::info("merge: RUN_A {} keyframes, {} clouds; RUN_B {} keyframes, {} clouds", n_a, clouds_a.size(),
               n_b, clouds_b.size());

  // 2. Place recognition, alignment, SLAM merge.
  const slam::MergedSessions m =
      slam::merge_sessions(std::move(map_a), map_b, vocabulary, o.config.slam.loop_closing.loop, o.search);
  const KeyframeId b_end = m.b_offset + map_b.map.last_keyframe_id() + 1;

  // 3. The semantic map from both runs' clouds at the merged poses, with the configured fusion.
  const pipeline::KeyframeStore store = merged_store(clouds_a, clouds_b, m.b_offset, m.map);
  pipeline::MapIntegrator semantic(o.config.map, o.config.dynamic.map_exclusions());
  semantic.rebuild(store);

  // 4. Outputs, staged: a merge that fails halfway leaves the folder as it was.
  io::StagedFolder staged(o.out_dir, "--out");
  const fs::path out(staged.path());
  slam::save_slam_map((out / pipeline::kSlamMapFile).string(), m.map, m.index, m.loop_edges, camera);
  pipeline::save_kept_clouds((out / pipeline::kKeptCloudsFile).string(), store);
  semantic.save((out / "map.ot").string(), (out / "map.ply").string());
  io::Trajectory keyframes;
  for (const auto& [id, kf] : m.map.keyframes()) keyframes.push_back({kf.t_s, kf.T_w_c});
  io::write_tum_trajectory((out / "keyframes.txt").string(), keyframes);
  const io::Trajectory traj_a = re_expressed(a.trajectory, m.map, m.correction, 0, m.b_offset);
  const io::Trajectory traj_b = re_expressed(b.trajectory, m.map, m.correction, m.b_offset, b_end);
  if (!traj_a.empty()) io::write_tum_trajectory((out / "trajectory_camera_a.txt").string(), traj_a);
  if (!traj_b.empty()) io::write_tum_trajectory((out / "trajectory_camera_b.txt").string(), traj_b);

  const slam::KeyFrame& ka = m.map.keyframe(m.a_keyframe);
  const slam::KeyFrame& kb = m.map.keyframe(m.b_keyframe);
  json j = {
      {"run_a", o.run_a},
      {"run_b", o.run_b},
      {"keyframes_a", n_a},
      {"keyframes_b", n_b},
      {"b_keyframe_id_offset", m.b_offset},
      {"matched",
       {{"a_keyframe", m.a_keyframe},
        {"a_frame_index", ka.frame_index},
        {"b_keyframe", m.b_keyframe - m.b_offset},
        {"b_frame_index", kb.frame_index},
        {"projection_matches", m.n_matches},
        {"verified_pairs", m.n_verified},
        {"agreeing_pairs", m.n_agreeing}}},
      {"T_a_b", pose_json(m.T_a_b)},
      {"fused_points", m.correction.n_fused},
      {"kept_clouds", {{"a", clouds_a.size()}, {"b", clouds_b.size()}}},
      {"map", semantic.describe()},
      {"outputs", {{"trajectory_camera_a", !traj_a.empty()}, {"trajectory_camera_b", !traj_b.empty()}}}};
  write_text_atomic((out / "merge.json").string(), j.dump(2) + "\n");
  staged.commit(merge_output_names(o.out_dir));
  return j;
}

io::Trajectory corrected_trajectory(const std::string& path, const std::map<double, SE3>& correction_at) {
  if (correction_at.empty()) return {};
  io::Trajectory out = io::read_tum_trajectory(path);
  for (auto& p : out) {
    auto hi = correction_at.lower_bound(p.t_s);
    auto near = hi;
    if (hi == correction_at.end() ||
        (hi != correction_at.begin() && p.t_s - std::prev(hi)->first < hi->first - p.t_s))
      near = std::prev(hi);
    p.T_w_x = near->second * p.T_w_x;
  }
  return out;
}

std::vector<std::string> merge_output_names(const std::string& out_dir) {
  std::vector<std::string> names = {pipeline::kSlamMapFile,
                                    pipeline::kKeptCloudsFile,
                                    "map.ot",
                                    "map.ply",
                                    "keyframes.txt",
                                    "merge.json",
                                    "unplaced"};
  std::error_code ec;
  for (const auto& e : fs::directory_iterator(out_dir, ec)) {
    const std::string n = e.path().filename().string();
    if (n.rfind("trajectory_camera_", 0) == 0 && e.path().extension() == ".txt") names.push_back(n);
  }
  return names;
}

}  // namespace s3m::run
