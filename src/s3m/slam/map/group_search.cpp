#include "s3m/slam/map/group_search.hpp"

#include <algorithm>
#include <set>

#include "s3m/features/orb_matcher.hpp"
#include "s3m/slam/map/point_fusion.hpp"

namespace s3m::slam {

std::vector<std::pair<int, PointId>> match_covisible_group(const features::FrameFeatures& f, const Map& map,
                                                           KeyframeId kf, const SE3& T_w_c,
                                                           const PinholeCamera& camera,
                                                           const GroupSearchParams& params) {
  std::vector<KeyframeId> group = map.keyframe(kf).best_covisible(params.group_size);
  group.push_back(kf);
  std::set<PointId> seen;
  std::vector<PointId> ids;
  std::vector<features::ProjectionQuery> queries;
  for (KeyframeId g : group)
    for (PointId pid : map.keyframe(g).points) {
      if (pid == kNoId || !map.has_point(pid) || !seen.insert(pid).second) continue;
      const MapPoint& p = map.point(pid);
      if (p.bad || (params.skip_observed_by != kNoId && p.observations.count(params.skip_observed_by)))
        continue;
      Visibility vis;
      if (!predict_visibility(p.p_w, p.normal_w, p.min_dist_m, p.max_dist_m, T_w_c, camera, f.pyramid, vis))
        continue;
      features::ProjectionQuery q;
      q.u = vis.uv.x();
      q.v = vis.uv.y();
      q.min_level = std::max(0, vis.level - 1);
      q.max_level = vis.level + params.levels_above;
      q.radius_px = params.radius_factor * f.pyramid.scale[size_t(vis.level)];
      q.descriptor = p.descriptor.data();
      queries.push_back(q);
      ids.push_back(pid);
    }
  features::ProjectionMatchParams mp;
  mp.max_distance = params.max_distance;
  mp.ratio = params.ratio;
  std::vector<char> taken(size_t(f.size()), 0);
  const std::vector<int> hit = features::match_by_projection(f, queries, mp, taken);
  std::vector<std::pair<int, PointId>> out;
  for (size_t q = 0; q < hit.size(); ++q)
    if (hit[q] >= 0) out.emplace_back(hit[q], ids[q]);
  return out;
}

}  // namespace s3m::slam
