// Full bundle adjustment of a map (bundle_adjustment.hpp): the end-of-run refinement and the
// corrections after a loop or a merge.
#include <map>
#include <vector>

#include "s3m/slam/optim/bundle_adjustment.hpp"

namespace s3m::slam {

int global_bundle_adjustment(Map& map, const PinholeCamera& camera, const BaConfig& config,
                             bool hold_large_steps, const std::vector<KeyframeLink>& links) {
  BaProblem problem;
  std::map<KeyframeId, int> frame_of;
  for (const auto& [id, kf] : map.keyframes()) {
    frame_of[id] = int(problem.T_c_w.size());
    problem.T_c_w.push_back(kf.T_w_c.inverse());
    problem.fixed.push_back(kf.is_root() ? 1 : 0);
  }
  std::vector<PointId> point_ids;
  for (const auto& [pid, p] : map.points()) {
    if (p.bad || p.observations.size() < 2) continue;
    const int point = int(problem.p_w.size());
    problem.p_w.push_back(p.p_w);
    point_ids.push_back(pid);
    for (const auto& [k, idx] : p.observations)
      problem.obs.push_back(keypoint_ba_observation(*map.keyframe(k).features, idx, frame_of.at(k), point));
  }
  if (problem.obs.empty()) return 0;
  for (const KeyframeLink& l : links) {
    const auto a = frame_of.find(l.from), b = frame_of.find(l.to);
    if (a != frame_of.end() && b != frame_of.end())
      problem.links.push_back({a->second, b->second, l.T_from_to, l.sigma_rad, l.sigma_m});
  }
  const BaProblem before = problem;
  BaResult r = bundle_adjust(problem, camera, config);
  if (hold_large_steps && hold_keyframes_moved_too_far(before, problem, config) > 0) {
    const std::vector<char> held = problem.fixed;
    problem = before;
    problem.fixed = held;
    r = bundle_adjust(problem, camera, config);
  }
  for (const auto& [id, f] : frame_of) map.set_keyframe_pose(id, problem.T_c_w[size_t(f)].inverse());
  for (size_t i = 0; i < point_ids.size(); ++i) map.set_point_position(point_ids[i], problem.p_w[i]);
  return r.n_outliers;
}

}  // namespace s3m::slam
