#pragma once
// Fusion of duplicate map points: project points into a keyframe and, where a keypoint matches,
// either add the observation or merge the two points (the better-observed one survives).
#include <vector>

#include "s3m/core/camera.hpp"
#include "s3m/slam/map/map.hpp"

namespace s3m::slam {

struct FusionConfig {
  double radius_factor = 3.0;  // search radius = radius_factor * level scale [px]
  int max_distance = 50;       // Hamming
  double chi2_mono = 5.991, chi2_stereo = 7.815;
};

// Projects points into keyframe kf and fuses them with its keypoints. Returns the number of
// points fused or newly observed.
int fuse_points(Map& map, KeyframeId kf, const std::vector<PointId>& points, const PinholeCamera& camera,
                const FusionConfig& config = {});

// Whether a point may be observed from camera pose T_w_c (in front, inside the image, within its
// scale-invariance distance range and viewing cone). Sets predicted pixel, distance and level.
struct Visibility {
  Eigen::Vector2d uv = Eigen::Vector2d::Zero();
  double u_right = features::kNoRight;  // predicted virtual right coordinate [px]
  double depth_m = 0;                   // predicted depth [m]
  double dist_m = 0;
  double view_cos = 1;
  int level = 0;
};
bool predict_visibility(const Vec3& p_w, const Vec3& normal_w, double min_dist_m, double max_dist_m,
                        const SE3& T_w_c, const PinholeCamera& camera, const features::ScalePyramid& pyr,
                        Visibility& out);

}  // namespace s3m::slam
