// Merging two sub-maps (map_merge.hpp): online from the loop closer, offline for two saved maps.
#include "s3m/slam/loop/map_merge.hpp"

#include <algorithm>
#include <cmath>
#include <optional>
#include <vector>

#include <fmt/format.h>

#include "s3m/core/error.hpp"
#include "s3m/slam/map/point_fusion.hpp"

namespace s3m::slam {

void MergeConfig::validate() const {
  require(start_frames >= 1 && lost_frames >= 1,
          "loop_closing.merge: start_frames and lost_frames must be >= 1 (got " +
              std::to_string(start_frames) + ", " + std::to_string(lost_frames) + ")");
  require(world == "first" || world == "largest",
          "loop_closing.merge.world: expected 'first' or 'largest', got '" + world + "'");
}

void SessionMergeConfig::validate() const {
  require(candidates_per_keyframe >= 1 && min_agreeing >= 1,
          "merge: candidates_per_keyframe and min_agreeing must be >= 1");
  require(agree_m > 0 && agree_deg > 0, "merge: agreement tolerances must be > 0");
}

std::optional<LoopCloser::Recognition> LoopCloser::recognise(const Map& map, KeyframeId kf,
                                                             const std::vector<KeyframeId>& candidates,
                                                             VerifyStats* stats) const {
  const auto v = verify(map, kf, candidates, stats);
  if (!v) return std::nullopt;
  return Recognition{v->loop_kf, v->T_w_cur, int(v->matches.size())};
}

std::optional<LoopCorrection> LoopCloser::merge_at(Map& map, KeyframeId kf,
                                                   const std::vector<KeyframeId>& candidates,
                                                   VerifyStats* stats) {
  std::vector<KeyframeId> other;
  for (KeyframeId c : candidates)
    if (map.keyframe(c).submap != map.keyframe(kf).submap) other.push_back(c);
  const auto v = verify(map, kf, other, stats);
  if (!v) return std::nullopt;
  return merge(map, kf, *v);
}

LoopCorrection LoopCloser::merge(Map& map, KeyframeId cur_id, const Verified& v) {
  LoopCorrection out;
  out.current_kf = cur_id;
  out.loop_kf = v.loop_kf;
  out.n_matches = int(v.matches.size());
  for (const auto& [id, kf] : map.keyframes()) out.T_w_kf_before[id] = kf.T_w_c;

  // 1. The younger sub-map moves rigidly into the older one's frame; its spanning tree hangs below
  //    the matched keyframe (the path to its old root reversed).
  const int cur_sub = map.keyframe(cur_id).submap, loop_sub = map.keyframe(v.loop_kf).submap;
  const SE3 T_loop_cur = v.T_w_cur * map.keyframe(cur_id).T_w_c.inverse();  // cur's frame -> loop's
  const int older = std::min(cur_sub, loop_sub);
  const KeyframeId seam = cur_sub > loop_sub ? cur_id : v.loop_kf;  // the moved side's keyframe at the seam
  std::set<KeyframeId> held;                                        // the older sub-map: stays where it is
  for (const auto& [id, kf] : map.keyframes())
    if (kf.submap == older) held.insert(id);
  if (cur_sub > loop_sub) {
    out.merged_from = cur_sub, out.merged_into = loop_sub, out.T_into_from = T_loop_cur;
    map.move_submap(cur_sub, loop_sub, T_loop_cur);
    map.join_tree(cur_id, v.loop_kf);
  } else {
    out.merged_from = loop_sub, out.merged_into = cur_sub, out.T_into_from = T_loop_cur.inverse();
    map.move_submap(loop_sub, cur_sub, T_loop_cur.inverse());
    map.join_tree(v.loop_kf, cur_id);
  }
  out.T_loop_current = map.keyframe(v.loop_kf).T_w_c.inverse() * map.keyframe(cur_id).T_w_c;
  std::map<KeyframeId, SE3> aligned;
  for (const auto& [id, kf] : map.keyframes()) aligned[id] = kf.T_w_c;

  // 2. The current side's points into the loop group's keyframes (weld() fuses the other way).
  std::set<KeyframeId> group{cur_id};
  std::map<KeyframeId, std::set<KeyframeId>> neighbours_before;
  for (const auto& [n, w] : map.keyframe(cur_id).covisibility) group.insert(n);
  std::vector<PointId> cur_points;
  for (KeyframeId k : group) {
    for (const auto& [n, w] : map.keyframe(k).covisibility) neighbours_before[k].insert(n);
    for (PointId pid : map.keyframe(k).points)
      if (pid != kNoId) cur_points.push_back(pid);
  }
  std::sort(cur_points.begin(), cur_points.end());
  cur_points.erase(std::unique(cur_points.begin(), cur_points.end()), cur_points.end());
  std::vector<KeyframeId> loop_group = map.keyframe(v.loop_kf).best_covisible(config_.loop_group_size);
  loop_group.push_back(v.loop_kf);
  for (KeyframeId k : loop_group)
    if (map.has_keyframe(k)) out.n_fused += fuse_points(map, k, cur_points, camera_);
  for (KeyframeId k : loop_group)
    if (map.has_keyframe(k)) map.update_covisibility(k);

  // 3. Welding BA: the moved side's seam keyframe and its covisible keyframes of that side, refined
  //    on the points both sides now share, the older side held.
  map.update_covisibility(seam);
  std::set<KeyframeId> window{seam};
  for (KeyframeId k : map.keyframe(seam).best_covisible())
    if (!held.count(k) && int(window.size()) < config_.ba.max_local_keyframes) window.insert(k);
  weld_bundle_adjustment(map, window, camera_, config_.ba);

  // 4. Fusion of the loop points into the current group, links across the seam, and the essential
  //    graph over both sides with the older sub-map and the welded window held.
  held.insert(window.begin(), window.end());
  weld(map, cur_id, v, group, neighbours_before, aligned, held, out);
  loop_edges_.emplace_back(cur_id, v.loop_kf);
  // 5. One BA over the whole map (the sub-map roots held): both sides settle on what they share.
  if (config_.merge.global_ba || config_.global_ba) {
    BaConfig ba = config_.ba;
    ba.first_iterations = ba.second_iterations = ba.global_iterations;
    global_bundle_adjustment(map, camera_, ba);
  }
  for (const auto& [id, kf] : map.keyframes()) out.T_w_kf_after[id] = kf.T_w_c;
  return out;
}

namespace {

double angle_deg(const SE3& T) { return rotation_angle_rad(T.linear()) * 180.0 / M_PI; }

struct Hit {
  KeyframeId b_kf, a_kf;
  SE3 T_a_b;
  int n_matches;
};

// Steps 1-3 of the offline merge: A and B in one map (B as sub-map 1), every B keyframe verified
// against its best-scoring A keyframes, and the best-supported pair enough others agree with.
struct SessionSearch {
  Map map;
  KeyframeId b_offset = 0;
  std::unique_ptr<LoopCloser> closer;
  std::vector<Hit> hits;
  std::optional<Hit> best;
  int n_queried = 0, n_agreeing = 0, most_agreeing = 0;
  VerifyStats stats;
};

SessionSearch search_sessions(LoadedSlamMap a, const LoadedSlamMap& b,
                              std::shared_ptr<const features::Vocabulary> vocabulary, const LoopConfig& loop,
                              const SessionMergeConfig& config) {
  config.validate();
  SessionSearch s;
  s.map = std::move(a.map);
  // 1. One map: B as sub-map 1 with shifted ids, its stored BoW vectors and loop edges.
  s.b_offset = s.map.append(b.map, 1);
  for (const auto& [id, kf] : b.map.keyframes())
    if (const KeyFrameBow* bow = b.index.find(id)) a.index.restore(id + s.b_offset, *bow);
  for (const auto& [cur, lp] : b.loop_edges) a.loop_edges.emplace_back(cur + s.b_offset, lp + s.b_offset);
  s.closer = std::make_unique<LoopCloser>(std::move(vocabulary), a.camera, loop);
  LoopCloser& closer = *s.closer;
  closer.index() = std::move(a.index);
  closer.index().sync(s.map);
  closer.restore_loop_edges(std::move(a.loop_edges));

  // 2. Every B keyframe against its best-scoring A keyframes: geometric verification only.
  for (const auto& [id, kf] : s.map.keyframes()) {
    if (kf.submap != 1) continue;
    ++s.n_queried;
    const auto found = closer.index().database().query(closer.index().find(id)->bow, 0, [&](int c) {
      return s.map.has_keyframe(KeyframeId(c)) && s.map.keyframe(KeyframeId(c)).submap == 0;
    });
    std::vector<KeyframeId> candidates;
    for (const auto& h : found)
      if (int(candidates.size()) < config.candidates_per_keyframe)
        candidates.push_back(KeyframeId(h.entry_id));
    if (const auto r = closer.recognise(s.map, id, candidates, &s.stats))
      s.hits.push_back({id, r->loop_kf, r->T_w_cur * kf.T_w_c.inverse(), r->n_matches});
  }
  // 3. The best-supported pair whose alignment enough other pairs agree with.
  for (const Hit& h : s.hits) {
    const int agreeing = int(std::count_if(s.hits.begin(), s.hits.end(), [&](const Hit& o) {
      const SE3 d = h.T_a_b.inverse() * o.T_a_b;
      return d.translation().norm() < config.agree_m && angle_deg(d) < config.agree_deg;
    }));
    s.most_agreeing = std::max(s.most_agreeing, agreeing);
    if (agreeing >= config.min_agreeing && (!s.best || h.n_matches > s.best->n_matches))
      s.best = h, s.n_agreeing = agreeing;
  }
  return s;
}

}  // namespace

SessionOverlap find_session_overlap(LoadedSlamMap a, const LoadedSlamMap& b,
                                    std::shared_ptr<const features::Vocabulary> vocabulary,
                                    const LoopConfig& loop, const SessionMergeConfig& config) {
  const SessionSearch s = search_sessions(std::move(a), b, std::move(vocabulary), loop, config);
  SessionOverlap o;
  o.n_verified = int(s.hits.size());
  if (!s.best) return o;
  o.placed = true;
  o.n_agreeing = s.n_agreeing;
  o.n_matches = s.best->n_matches;
  return o;
}

MergedSessions merge_sessions(LoadedSlamMap a, const LoadedSlamMap& b,
                              std::shared_ptr<const features::Vocabulary> vocabulary, const LoopConfig& loop,
                              const SessionMergeConfig& config) {
  SessionSearch s = search_sessions(std::move(a), b, std::move(vocabulary), loop, config);
  if (!s.best)
    throw Error(fmt::format(
        "merge: the two maps do not overlap: none of run B's {} keyframes was recognised in run A's {} "
        "keyframes "
        "(tried {} keyframe pairs, the best {} A keyframes by BoW score for each B keyframe; {} had enough "
        "BoW "
        "matches and a 3D-3D RANSAC pose; the best guided search found {} of the {} matches needed; {} pairs "
        "verified, at most {} agreeing on one alignment, {} needed)",
        s.n_queried, s.map.n_keyframes() - s.n_queried, s.stats.candidates, config.candidates_per_keyframe,
        s.stats.bow_matched, s.stats.best_matches, loop.min_projection_matches, s.hits.size(),
        s.most_agreeing, config.min_agreeing));
  // 4. Merge at that pair (verified again, deterministically, and applied).
  const auto correction = s.closer->merge_at(s.map, s.best->b_kf, {s.best->a_kf});
  require(correction.has_value(), "merge: the verified pair did not verify again (a bug)");
  MergedSessions m{std::move(s.map),
                   std::move(s.closer->index()),
                   s.closer->loop_edges(),
                   s.b_offset,
                   SE3::Identity(),
                   kNoId,
                   kNoId,
                   0,
                   0,
                   int(s.hits.size()),
                   *correction};
  m.n_agreeing = s.n_agreeing;
  m.b_keyframe = s.best->b_kf;
  m.a_keyframe = s.best->a_kf;
  m.T_a_b = s.best->T_a_b;
  m.n_matches = s.best->n_matches;
  return m;
}

}  // namespace s3m::slam
