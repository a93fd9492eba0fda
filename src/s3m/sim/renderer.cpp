#include "s3m/sim/renderer.hpp"

#include <array>
#include <cmath>

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <opencv2/imgproc.hpp>

#include "s3m/core/error.hpp"
#include "s3m/sim/texture.hpp"

namespace s3m::sim {
namespace {

constexpr float kLightGain = 1.4f;     // diffuse gain of a light at unit distance
constexpr float kLightFalloff = 0.3f;  // 1 / (1 + k d^2) attenuation [1/m^2]

// Linear [0, 1] -> 8-bit sRGB, tabulated (pow() per pixel would dominate the frame time).
const std::array<std::uint8_t, 4096>& srgb_table() {
  static const std::array<std::uint8_t, 4096> table = [] {
    std::array<std::uint8_t, 4096> t{};
    for (int i = 0; i < 4096; ++i) {
      const double x = i / 4095.0;
      const double s = x <= 0.0031308 ? 12.92 * x : 1.055 * std::pow(x, 1.0 / 2.4) - 0.055;
      t[i] = static_cast<std::uint8_t>(std::lround(255.0 * s));
    }
    return t;
  }();
  return table;
}
inline std::uint8_t to_srgb(const std::uint8_t* table, float x) {
  return table[static_cast<int>(std::min(std::max(x, 0.0f), 1.0f) * 4095.0f + 0.5f)];
}

// Outward unit normal of the primitive surface nearest to p_p (primitive frame).
Eigen::Vector3f local_normal(Shape shape, const Eigen::Vector3f& h, const Eigen::Vector3f& p) {
  switch (shape) {
    case Shape::kBox: {
      int k = 0;
      const Eigen::Vector3f gap = h - p.cwiseAbs();
      gap.minCoeff(&k);
      Eigen::Vector3f n = Eigen::Vector3f::Zero();
      n[k] = p[k] >= 0 ? 1.0f : -1.0f;
      return n;
    }
    case Shape::kCylinder: {
      const float rxy = p.head<2>().norm();
      if (h.z() - std::abs(p.z()) < h.x() - rxy || rxy < 1e-6f) return {0, 0, p.z() >= 0 ? 1.0f : -1.0f};
      return {p.x() / rxy, p.y() / rxy, 0};
    }
    case Shape::kSphere: return p.normalized();
  }
  return {0, 0, 1};
}

}  // namespace

Renderer::Renderer(const Scene& scene, const SensorConfig& sensor)
    : scene_(scene), sensor_(sensor), raycaster_(scene_) {
  sensor_.validate();
  // 1 / |(x, y, 1)| per pixel: the ray length per unit depth does not depend on the pose.
  const PinholeCamera& c = sensor_.camera;
  inv_ray_length_.create(c.height, c.width, CV_32FC1);
  for (int v = 0; v < c.height; ++v)
    for (int u = 0; u < c.width; ++u) {
      const double x = (u - c.cx) / c.fx, y = (v - c.cy) / c.fy;
      inv_ray_length_.at<float>(v, u) = static_cast<float>(1.0 / std::sqrt(x * x + y * y + 1.0));
    }
  for (const auto& p : scene_.primitives) prim_cache_.push_back(cache_of(p));
}

Renderer::PrimCache Renderer::cache_of(const Primitive& p) {
  const SE3 T_p_w = p.T_w_p.inverse();
  return {T_p_w.linear().cast<float>(), p.T_w_p.linear().cast<float>(), T_p_w.translation().cast<float>(),
          p.half_extents_m.cast<float>()};
}

namespace {
Scene scene_of(const std::vector<Primitive>& primitives) {
  Scene s;
  s.primitives = primitives;
  return s;
}
}  // namespace

MovingLayer::MovingLayer(std::vector<Primitive> primitives)
    : primitives_(std::move(primitives)), raycaster_(scene_of(primitives_)) {}

IdealView Renderer::render_ideal(const SE3& T_w_c, const MovingLayer* movers) const {
  return render_rows(&T_w_c, false, movers);
}

IdealView Renderer::render_ideal(const std::vector<SE3>& T_w_c_of_row, const MovingLayer* movers) const {
  require(static_cast<int>(T_w_c_of_row.size()) == sensor_.camera.height,
          "Renderer::render_ideal: need one pose per image row");
  return render_rows(T_w_c_of_row.data(), true, movers);
}

cv::Mat Renderer::moving_mask(const IdealView& v) const {
  cv::Mat mask;
  cv::compare(v.prim_ids, static_cast<double>(scene_.primitives.size()), mask, cv::CMP_GE);
  return mask;
}

IdealView Renderer::render_rows(const SE3* T_w_c, bool per_row, const MovingLayer* movers) const {
  const PinholeCamera& cam = sensor_.camera;
  const int W = cam.width, H = cam.height;
  IdealView v;
  v.rgb.create(H, W, CV_8UC3);
  v.depth_m.create(H, W, CV_32FC1);
  v.labels.create(H, W, CV_16UC1);
  v.prim_ids.create(H, W, CV_32SC1);
  v.albedo_lum.create(H, W, CV_32FC1);
  v.cos_incidence.create(H, W, CV_32FC1);
  struct Light {  // position and gain, in float
    Eigen::Vector3f p;
    float gain;
  };
  std::vector<Light> lights;
  const std::uint8_t* srgb = srgb_table().data();
  for (const auto& l : scene_.lights)
    lights.push_back({l.position_w.cast<float>(), kLightGain * l.intensity});
  // Moving primitives follow the static ones: id n_static + k.
  const int n_static = static_cast<int>(scene_.primitives.size());
  const bool moving = movers && !movers->primitives().empty();
  std::vector<PrimCache> mover_cache;
  if (moving)
    for (const auto& p : movers->primitives()) mover_cache.push_back(cache_of(p));

  tbb::parallel_for(tbb::blocked_range<int>(0, H, 4), [&](const tbb::blocked_range<int>& rows) {
    RayPacket pk;
    for (int r = rows.begin(); r < rows.end(); ++r) {
      const SE3& T = T_w_c[per_row ? r : 0];
      const Eigen::Matrix3f R_w_c = T.linear().cast<float>();
      const Eigen::Vector3f o_w = T.translation().cast<float>();
      const float* inv_len = inv_ray_length_.ptr<float>(r);
      for (int u0 = 0; u0 < W; u0 += kPacket) {
        // 1. Rays with camera-frame direction (x, y, 1): the hit parameter t is the z depth.
        Eigen::Vector3f d_w[kPacket];
        for (int i = 0; i < kPacket; ++i) {
          const int u = u0 + i;
          d_w[i] = R_w_c * Eigen::Vector3f(static_cast<float>((u - cam.cx) / cam.fx),
                                           static_cast<float>((r - cam.cy) / cam.fy), 1.0f);
          pk.ox[i] = o_w.x(), pk.oy[i] = o_w.y(), pk.oz[i] = o_w.z();
          pk.dx[i] = d_w[i].x(), pk.dy[i] = d_w[i].y(), pk.dz[i] = d_w[i].z();
          pk.t_max[i] = 1000.0f;
          pk.active[i] = u < W ? -1 : 0;
        }
        raycaster_.intersect(pk);
        if (moving) {  // a mover in front of the static hit replaces it
          RayPacket mk = pk;
          for (int i = 0; i < kPacket; ++i) mk.t_max[i] = std::isfinite(pk.t_hit[i]) ? pk.t_hit[i] : 1000.0f;
          movers->raycaster().intersect(mk);
          for (int i = 0; i < kPacket; ++i)
            if (mk.prim[i] >= 0 && mk.t_hit[i] < pk.t_hit[i])
              pk.t_hit[i] = mk.t_hit[i], pk.prim[i] = n_static + mk.prim[i];
        }
        // 2. Shade: procedural albedo x (ambient + Lambertian point lights).
        auto* bgr = v.rgb.ptr<cv::Vec3b>(r);
        auto* depth = v.depth_m.ptr<float>(r);
        auto* label = v.labels.ptr<std::uint16_t>(r);
        auto* prim_id = v.prim_ids.ptr<int>(r);
        auto* lum = v.albedo_lum.ptr<float>(r);
        auto* cosi = v.cos_incidence.ptr<float>(r);
        for (int i = 0; i < kPacket && u0 + i < W; ++i) {
          const int u = u0 + i, id = pk.prim[i];
          prim_id[u] = id;
          if (id < 0) {
            bgr[u] = {0, 0, 0};
            depth[u] = lum[u] = cosi[u] = 0.0f;
            label[u] = cls::kUnknown;
            continue;
          }
          const bool mover = id >= n_static;
          const Primitive& prim = mover ? movers->primitives()[id - n_static] : scene_.primitives[id];
          const PrimCache& pc = mover ? mover_cache[id - n_static] : prim_cache_[id];
          const Eigen::Vector3f p_w = o_w + pk.t_hit[i] * d_w[i];
          const Eigen::Vector3f p_p = pc.R_p_w * p_w + pc.t_p_w;
          const Eigen::Vector3f n_p = local_normal(prim.shape, pc.half_m, p_p);
          Eigen::Vector3f n_w = pc.R_w_p * n_p;
          const float dn = n_w.dot(d_w[i]) * inv_len[u];
          if (dn > 0) n_w = -n_w;  // seen from behind (inside a primitive): light the visible side
          const Eigen::Vector3f a = albedo(prim.material, prim.shape, pc.half_m, p_p, n_p);
          float light = scene_.ambient;
          for (const auto& l : lights) {
            const Eigen::Vector3f L = l.p - p_w;
            const float d2 = L.squaredNorm();
            light += std::max(0.0f, n_w.dot(L)) * l.gain / (std::sqrt(d2) * (1.0f + kLightFalloff * d2));
          }
          bgr[u] = {to_srgb(srgb, a.z() * light), to_srgb(srgb, a.y() * light), to_srgb(srgb, a.x() * light)};
          depth[u] = pk.t_hit[i];
          label[u] = prim.label;
          lum[u] = 0.2126f * a.x() + 0.7152f * a.y() + 0.0722f * a.z();
          cosi[u] = std::abs(dn);
        }
      }
    }
  });
  return v;
}

}  // namespace s3m::sim
