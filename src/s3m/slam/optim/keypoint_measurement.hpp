#pragma once
// What an RGB-D keypoint measures of a map point, one rule for pose-only optimisation, bundle
// adjustment (Ceres, with T = ceres::Jet) and point fusion's gate:
//   - two pixel rows (u, v), weighted by the keypoint level's 1 / sigma [1/px];
//   - with depth, a third row: the inverse depth rho = 1/z [1/m] weighted by its own information
//     (features::FrameFeatures::inverse_depth_info, DepthNoiseConfig "sensor"), or, without that,
//     ORB-SLAM's virtual right coordinate u - bf / z [px] with the pixel weight ("virtual_right").
// Keeping the rule in one place keeps the optimisers' residuals and their chi2 outlier gates in
// agreement; a change to the depth model (e.g. a gate robust to a wrong sigma) goes here.
#include <cmath>

#include <Eigen/Core>

#include "s3m/core/camera.hpp"
#include "s3m/features/frame_features.hpp"

namespace s3m::slam {

// What keypoint i of f measures: its pixel with the level weight, the virtual right coordinate
// and, with depth, the inverse depth with its weight. Obs: PoseObservation or BaObservation
// (fields uv, u_right, inv_sigma2, rho, inv_rho_sigma2).
template <class Obs>
void set_keypoint_measurement(const features::FrameFeatures& f, int i, Obs& o) {
  const auto& kp = f.keypoints[std::size_t(i)];
  o.uv = {kp.pt.x, kp.pt.y};
  o.u_right = f.u_right[std::size_t(i)];
  o.inv_sigma2 = f.pyramid.inv_sigma2[std::size_t(kp.octave)];
  if (f.has_depth(i)) {
    o.rho = 1.0 / f.depth_m[std::size_t(i)];
    o.inv_rho_sigma2 = f.inverse_depth_info(i);
  }
}

// The depth row of one observation: residual, its chi2 and its whitened Jacobian.
class DepthRow {
 public:
  template <class Obs>
  explicit DepthRow(const Obs& o)
      : u_right_(o.u_right),
        rho_(o.rho),
        w2_(o.inv_sigma2),
        wr2_(o.inv_rho_sigma2),
        w_(std::sqrt(o.inv_sigma2)),
        wr_(o.inv_rho_sigma2 > 0 ? std::sqrt(o.inv_rho_sigma2) : 0.0) {}

  bool present() const { return features::has_right(u_right_); }  // else monocular (2 rows)

  // Whitened residual for the predicted pixel column pu [px] and inverse depth iz [1/m].
  template <class T>
  T residual(const T& pu, const T& iz, double bf) const {
    if (wr_ > 0) return wr_ * (iz - rho_);
    return w_ * (pu - bf * iz - u_right_);
  }

  // Its chi2 (the squared whitened residual) for the predicted column pu and depth z [m].
  double chi2(double pu, double z, double bf) const {
    if (wr2_ > 0) {
      const double e = 1.0 / z - rho_;
      return e * e * wr2_;
    }
    const double e = pu - bf / z - u_right_;
    return e * e * w2_;
  }

  // d residual / d p_c (whitened) at the camera-frame point p.
  Eigen::RowVector3d jacobian(const Vec3& p, const PinholeCamera& cam) const {
    const double iz = 1.0 / p.z(), iz2 = iz * iz;
    if (wr_ > 0) return {0.0, 0.0, -wr_ * iz2};
    return Eigen::RowVector3d(cam.fx * iz, 0.0, -cam.fx * p.x() * iz2 + cam.bf * iz2) * w_;
  }

 private:
  double u_right_, rho_, w2_, wr2_, w_, wr_;
};

}  // namespace s3m::slam
