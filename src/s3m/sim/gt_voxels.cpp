#include "s3m/sim/gt_voxels.hpp"

#include <array>
#include <cmath>
#include <map>
#include <tuple>

#include "s3m/core/error.hpp"

namespace s3m::sim {
namespace {

using V3 = Eigen::Vector3d;

// Surface samples of a primitive in its own frame, spaced at most step_m apart.
std::vector<V3> surface_samples(const Primitive& prim, double step) {
  std::vector<V3> pts;
  const V3 h = prim.half_extents_m;
  auto n_of = [&](double len) { return std::max(1, static_cast<int>(std::ceil(len / step))); };
  switch (prim.shape) {
    case Shape::kBox:
      for (int axis = 0; axis < 3; ++axis) {
        const int a = (axis + 1) % 3, b = (axis + 2) % 3;
        const int na = n_of(2 * h[a]), nb = n_of(2 * h[b]);
        for (int side : {-1, 1})
          for (int i = 0; i <= na; ++i)
            for (int j = 0; j <= nb; ++j) {
              V3 p;
              p[axis] = side * h[axis];
              p[a] = -h[a] + 2 * h[a] * i / na;
              p[b] = -h[b] + 2 * h[b] * j / nb;
              pts.push_back(p);
            }
      }
      break;
    case Shape::kCylinder: {
      const double r = h.x();
      const int nt = n_of(2 * M_PI * r), nz = n_of(2 * h.z()), nr = n_of(r);
      for (int i = 0; i < nt; ++i) {
        const double th = 2 * M_PI * i / nt;
        for (int j = 0; j <= nz; ++j) pts.emplace_back(r * std::cos(th), r * std::sin(th), -h.z() + 2 * h.z() * j / nz);
        for (int k = 0; k <= nr; ++k)
          for (int side : {-1, 1}) pts.emplace_back(r * k / nr * std::cos(th), r * k / nr * std::sin(th), side * h.z());
      }
      break;
    }
    case Shape::kSphere: {
      const double r = h.x();
      const int nl = n_of(M_PI * r);
      for (int i = 0; i <= nl; ++i) {
        const double th = M_PI * i / nl;
        const int np = n_of(2 * M_PI * r * std::sin(th));
        for (int k = 0; k < np; ++k) {
          const double ph = 2 * M_PI * k / np;
          pts.emplace_back(r * std::sin(th) * std::cos(ph), r * std::sin(th) * std::sin(ph), r * std::cos(th));
        }
      }
      break;
    }
  }
  return pts;
}

}  // namespace

io::GtVoxelMap voxelize_scene(const Scene& scene, double res) {
  require(res > 0 && std::isfinite(res), "voxelize_scene: resolution must be a positive number of metres");
  // Bounding spheres make the "buried inside another primitive" test cheap.
  std::vector<double> radius;
  for (const auto& p : scene.primitives) radius.push_back(p.half_extents_m.norm() + 1e-3);
  std::map<std::tuple<int, int, int>, std::array<int, cls::kCount>> votes;
  for (std::size_t i = 0; i < scene.primitives.size(); ++i) {
    const Primitive& prim = scene.primitives[i];
    for (const V3& p_p : surface_samples(prim, 0.5 * res)) {
      const V3 p_w = prim.T_w_p * p_p;
      if (!scene.room.contains(p_w, -1e-4)) continue;  // outer faces of the room shell
      bool buried = false;
      for (std::size_t k = 0; k < scene.primitives.size() && !buried; ++k) {
        if (k == i || (p_w - scene.primitives[k].T_w_p.translation()).norm() > radius[k]) continue;
        buried = signed_distance_m(scene.primitives[k], p_w) < -1e-4;
      }
      if (buried) continue;
      const auto key = std::make_tuple(static_cast<int>(std::floor(p_w.z() / res)),
                                       static_cast<int>(std::floor(p_w.y() / res)),
                                       static_cast<int>(std::floor(p_w.x() / res)));
      auto [it, fresh] = votes.try_emplace(key);
      if (fresh) it->second.fill(0);
      it->second[prim.label < cls::kCount ? prim.label : cls::kOther]++;
    }
  }
  io::GtVoxelMap map;
  map.resolution_m = res;
  for (const auto& [key, count] : votes) {
    int best = 0;
    for (int c = 1; c < cls::kCount; ++c)
      if (count[c] >= count[best]) best = c;  // ties go to the higher id: objects over the room shell
    const auto [iz, iy, ix] = key;
    map.centres_w.emplace_back(static_cast<float>((ix + 0.5) * res), static_cast<float>((iy + 0.5) * res),
                               static_cast<float>((iz + 0.5) * res));
    map.labels.push_back(static_cast<ClassId>(best));
  }
  return map;
}

}  // namespace s3m::sim
