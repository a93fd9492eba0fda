#pragma once
// Renders RGB, depth and class labels of a Scene from a camera pose by ray casting (Embree),
// then applies the sensor model. Rows are shaded in parallel with TBB; the result does not
// depend on the number of threads.
#include <cstdint>
#include <functional>
#include <vector>

#include <opencv2/core.hpp>

#include "s3m/core/rgbd_frame.hpp"
#include "s3m/core/se3.hpp"
#include "s3m/sim/raycaster.hpp"
#include "s3m/sim/scene.hpp"
#include "s3m/sim/sensor.hpp"

namespace s3m::sim {

// Exact, noise-free render of one view.
struct IdealView {
  cv::Mat rgb;            // CV_8UC3 BGR, shaded albedo (no optics blur, no noise)
  cv::Mat depth_m;        // CV_32FC1 exact z depth [m]; 0 where the ray hit nothing
  cv::Mat labels;         // CV_16UC1 class id of the surface hit (0 = none)
  cv::Mat prim_ids;       // CV_32SC1 index into Scene::primitives (-1 = none)
  cv::Mat albedo_lum;     // CV_32FC1 albedo luminance in [0, 1] (drives dark-surface dropout)
  cv::Mat cos_incidence;  // CV_32FC1 |cos| of the angle between ray and surface normal
};

// Primitives that move (people): one frame's positions, ray cast over the static scene through a
// small BVH of their own, so the static scene's BVH is built once. Their pixels get primitive ids
// after the static scene's (IdealView::prim_ids >= Scene::primitives.size()).
class MovingLayer {
 public:
  explicit MovingLayer(std::vector<Primitive> primitives);
  const std::vector<Primitive>& primitives() const { return primitives_; }
  const Raycaster& raycaster() const { return raycaster_; }

 private:
  std::vector<Primitive> primitives_;
  Raycaster raycaster_;
};

// Capture instants of one frame's two streams [s].
struct FrameTimes {
  double colour_s = 0;  // end of the exposure of the colour image's first row
  double depth_s = 0;   // the depth snapshot
};

class Renderer {
 public:
  Renderer(const Scene& scene, const SensorConfig& sensor);  // builds the BVH; keeps a copy of scene

  const PinholeCamera& camera() const { return sensor_.camera; }
  const SensorConfig& sensor() const { return sensor_; }
  const Scene& scene() const { return scene_; }

  // 1. cast one ray per pixel, 2. shade the hits. No sensor effects, no range limits.
  // movers (may be null): moving primitives drawn over the scene.
  IdealView render_ideal(const SE3& T_w_c, const MovingLayer* movers = nullptr) const;
  // The same with image row r seen from T_w_c_of_row[r] (a rolling shutter); one pose per row.
  IdealView render_ideal(const std::vector<SE3>& T_w_c_of_row, const MovingLayer* movers = nullptr) const;

  // A sensor frame at T_w_c: ideal render + sensor model (range limits, noise, dropouts, blur).
  // noise_seed selects the random draws (use a different one per frame). When
  // motion_blur_samples > 1, T_w_c_open is the pose when the shutter opened (else ignored).
  // With movers, RgbdFrame::dynamic_mask marks the pixels that see one.
  RgbdFrame render(const SE3& T_w_c, std::uint64_t noise_seed, const SE3* T_w_c_open = nullptr,
                   const MovingLayer* movers = nullptr) const;

  // A sensor frame whose parts are captured at different instants, for the sensor lies
  // (SensorConfig::timed()). T_w_c_at(t) is the colour camera's pose at time t [s]. Colour row r is
  // exposed until times.colour_s + rolling_shutter_s * r / (height - 1), motion-blurred over the
  // exposure_s before (motion_blur_samples > 1); depth is a snapshot at times.depth_s from the depth
  // camera, turned by depth_registration_error_px against the colour camera. Labels follow colour.
  RgbdFrame render_timed(const std::function<SE3(double)>& T_w_c_at, const FrameTimes& times,
                         std::uint64_t noise_seed, const MovingLayer* movers = nullptr) const;

 private:
  IdealView render_rows(const SE3* T_w_c, bool per_row, const MovingLayer* movers) const;
  // Pixels of an ideal view that see a moving primitive (255), for RgbdFrame::dynamic_mask.
  cv::Mat moving_mask(const IdealView& v) const;
  cv::Mat sensor_depth_image(IdealView& depth_view, std::uint64_t noise_seed) const;

  Scene scene_;
  SensorConfig sensor_;
  Raycaster raycaster_;
  struct PrimCache {  // single-precision pose data for the per-pixel shading
    Eigen::Matrix3f R_p_w, R_w_p;
    Eigen::Vector3f t_p_w, half_m;
  };
  static PrimCache cache_of(const Primitive& p);
  std::vector<PrimCache> prim_cache_;
  cv::Mat inv_ray_length_;  // CV_32FC1: 1 / |(x, y, 1)| of each pixel's ray
};

// Colour image of a label map using the indoor class palette (BGR), for pictures and debugging.
cv::Mat colourise_labels(const cv::Mat& labels16);
// Depth [m] as a turbo-coloured image, black where missing.
cv::Mat colourise_depth(const cv::Mat& depth_m, double max_m);

}  // namespace s3m::sim
