#include "s3m/slam/map/point_fusion.hpp"

#include <limits>

#include "s3m/features/orb_matcher.hpp"
#include "s3m/slam/optim/keypoint_measurement.hpp"
#include "s3m/slam/optim/pose_optimizer.hpp"

namespace s3m::slam {

bool predict_visibility(const Vec3& p_w, const Vec3& normal_w, double min_dist_m, double max_dist_m,
                        const SE3& T_w_c, const PinholeCamera& cam, const features::ScalePyramid& pyr,
                        Visibility& out) {
  const Vec3 p_c = T_w_c.inverse() * p_w;
  if (p_c.z() <= 1e-3) return false;
  out.uv = cam.project(p_c);
  if (!cam.in_image(out.uv.x(), out.uv.y())) return false;
  const Vec3 ray = p_w - T_w_c.translation();
  out.dist_m = ray.norm();
  if (out.dist_m < 0.8 * min_dist_m || out.dist_m > 1.2 * max_dist_m) return false;
  out.view_cos = ray.dot(normal_w) / out.dist_m;
  if (out.view_cos < 0.5) return false;
  out.level = predict_level(out.dist_m, max_dist_m, pyr);
  out.u_right = out.uv.x() - cam.bf / p_c.z();
  out.depth_m = p_c.z();
  return true;
}

int fuse_points(Map& map, KeyframeId kf_id, const std::vector<PointId>& points, const PinholeCamera& cam,
                const FusionConfig& cfg) {
  int n_fused = 0;
  for (PointId pid : points) {
    if (!map.has_point(pid)) continue;  // merged away earlier in this loop
    const KeyFrame& kf = map.keyframe(kf_id);
    const MapPoint& p = map.point(pid);
    if (p.observations.count(kf_id)) continue;
    const auto& F = *kf.features;
    // 1. Predict where and at which scale the keyframe should see the point.
    Visibility vis;
    if (!predict_visibility(p.p_w, p.normal_w, p.min_dist_m, p.max_dist_m, kf.T_w_c, cam, F.pyramid, vis))
      continue;
    const double radius = cfg.radius_factor * F.pyramid.scale[vis.level];
    // 2. Best keypoint in the window that also agrees geometrically.
    int best = std::numeric_limits<int>::max(), best_idx = -1;
    for (int i : F.in_area(vis.uv.x(), vis.uv.y(), radius, std::max(0, vis.level - 1), vis.level)) {
      const auto& kp = F.keypoints[i];
      const double inv_s2 = F.pyramid.inv_sigma2[kp.octave];
      double e2 = (vis.uv - Eigen::Vector2d(kp.pt.x, kp.pt.y)).squaredNorm();
      if (features::has_right(F.u_right[i])) {  // the depth row as in bundle adjustment
        PoseObservation m;
        set_keypoint_measurement(F, i, m);
        if (e2 * inv_s2 + DepthRow(m).chi2(vis.uv.x(), vis.depth_m, cam.bf) > cfg.chi2_stereo) continue;
      } else if (e2 * inv_s2 > cfg.chi2_mono) {
        continue;
      }
      const int d = features::descriptor_distance(p.descriptor.data(), F.descriptor(i));
      if (d < best) best = d, best_idx = i;
    }
    if (best_idx < 0 || best > cfg.max_distance) continue;
    // 3. Merge with the keypoint's point (keep the better observed) or add the observation.
    const PointId other = kf.points[best_idx];
    if (other != kNoId) {
      if (other == pid) continue;
      if (map.point(other).observations.size() > p.observations.size())
        map.replace_point(pid, other);
      else
        map.replace_point(other, pid);
    } else {
      map.add_observation(pid, kf_id, best_idx);
      map.update_point_appearance(pid);
    }
    ++n_fused;
  }
  return n_fused;
}

}  // namespace s3m::slam
