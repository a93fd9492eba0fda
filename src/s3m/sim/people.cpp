#include "s3m/sim/people.hpp"

#include <cmath>
#include <limits>

#include "s3m/core/config_table.hpp"
#include "s3m/core/error.hpp"
#include "s3m/sim/furniture.hpp"
#include "s3m/sim/rng.hpp"

namespace s3m::sim {
namespace {

constexpr int kAttempts = 400;          // candidate paths per person
constexpr double kWallMargin_m = 0.45;  // path ends stay this far inside the walls
constexpr double kMaxPath_m = 5.0;

// Smallest clearance of a body of radius r walking from a to b (furniture, static people, walls).
bool path_is_clear(const Scene& scene, const Walker& w) {
  const double len = (w.b - w.a).norm();
  const int n = std::max(2, static_cast<int>(std::ceil(len / 0.1)));
  for (int i = 0; i <= n; ++i) {
    const Eigen::Vector2d p = w.a + (w.b - w.a) * (static_cast<double>(i) / n);
    for (double z : {0.3, 0.9, 1.5})
      if (scene.clearance_m({p.x(), p.y(), z}) < w.radius_m + 0.05) return false;
  }
  return true;
}

// Smallest horizontal distance between the walker's body and the camera while the camera is
// below head height (+0.3 m) over the whole flight [m].
double camera_gap_m(const Walker& w, const Trajectory& t) {
  double gap = std::numeric_limits<double>::infinity();
  for (const TrajectorySample& s : t.samples) {
    const Eigen::Vector3d c = s.T_w_c.translation();
    if (c.z() > w.height_m + 0.3) continue;
    gap = std::min(gap, (c.head<2>() - w.position(s.t_s)).norm() - w.radius_m);
  }
  return gap;
}

Walker random_walker(const Scene& scene, const PeopleConfig& cfg, Rng& rng) {
  Walker w;
  const Eigen::Vector3d lo = scene.room.min, hi = scene.room.max;
  w.a = {rng.uniform(lo.x() + kWallMargin_m, hi.x() - kWallMargin_m),
         rng.uniform(lo.y() + kWallMargin_m, hi.y() - kWallMargin_m)};
  const double heading = rng.uniform(0, 2 * M_PI);
  const double len = rng.uniform(cfg.min_path_m, std::max(cfg.min_path_m, kMaxPath_m));
  w.b = w.a + len * Eigen::Vector2d(std::cos(heading), std::sin(heading));
  w.speed_mps = cfg.speed_mps * rng.uniform(0.8, 1.2);
  w.phase_m = rng.uniform(0, 2 * len);
  w.height_m = rng.uniform(1.6, 1.9);
  w.radius_m = rng.uniform(0.17, 0.22);
  const Eigen::Vector3f shirt(static_cast<float>(rng.uniform(0.1, 0.8)),
                              static_cast<float>(rng.uniform(0.1, 0.8)),
                              static_cast<float>(rng.uniform(0.1, 0.8)));
  w.clothes = mat(Pattern::kFabric, shirt, shirt * 0.55f, 0.08f);
  w.clothes.seed = static_cast<std::uint32_t>(rng.next());
  w.skin = mat(Pattern::kPaint, {0.8f, 0.6f, 0.48f}, {0.7f, 0.5f, 0.4f}, 0.05f);
  w.skin.seed = static_cast<std::uint32_t>(rng.next());
  return w;
}

bool inside_room(const Scene& scene, const Eigen::Vector2d& p) {
  return p.x() > scene.room.min.x() + kWallMargin_m && p.x() < scene.room.max.x() - kWallMargin_m &&
         p.y() > scene.room.min.y() + kWallMargin_m && p.y() < scene.room.max.y() - kWallMargin_m;
}

}  // namespace

void PeopleConfig::validate() const {
  require(count >= 0 && count <= 20, "sim: people.count must be in [0, 20]");
  require(speed_mps > 0 && speed_mps <= 3, "sim: people.speed_mps must be in (0, 3] m/s");
  require(min_path_m >= 0.5 && min_path_m <= kMaxPath_m, "sim: people.min_path_m must be in [0.5, 5] m");
  require(camera_gap_m >= 0 && camera_gap_m <= 3, "sim: people.camera_gap_m must be in [0, 3] m");
}

void fields(config::FieldVisitor& v, PeopleConfig& c) {
  v("count", c.count);
  v("speed_mps", c.speed_mps);
  v("min_path_m", c.min_path_m);
  v("camera_gap_m", c.camera_gap_m);
}

Eigen::Vector2d Walker::position(double t_s) const {
  const double len = (b - a).norm();
  if (len <= 0) return a;
  double s = std::fmod(phase_m + speed_mps * t_s, 2 * len);
  if (s < 0) s += 2 * len;
  return s < len ? a + (b - a) * (s / len) : b + (a - b) * ((s - len) / len);
}

double Walker::heading_rad(double t_s) const {
  const double len = (b - a).norm();
  double s = std::fmod(phase_m + speed_mps * t_s, 2 * len);
  if (s < 0) s += 2 * len;
  const Eigen::Vector2d d = s < len ? b - a : a - b;
  return std::atan2(d.y(), d.x());
}

std::vector<Walker> plan_walkers(const Scene& scene, const Trajectory& trajectory, const PeopleConfig& cfg,
                                 std::uint64_t seed) {
  cfg.validate();
  std::vector<Walker> out;
  for (int i = 0; i < cfg.count; ++i) {
    Rng rng(hash3(seed, 0x9E0F1Eull, static_cast<std::uint64_t>(i)));
    Walker best;
    double best_gap = -std::numeric_limits<double>::infinity();
    for (int k = 0; k < kAttempts; ++k) {
      const Walker w = random_walker(scene, cfg, rng);
      if (!inside_room(scene, w.b) || !path_is_clear(scene, w)) continue;
      const double gap = camera_gap_m(w, trajectory);
      if (gap > best_gap) best = w, best_gap = gap;
      if (gap >= cfg.camera_gap_m) break;
    }
    require(best_gap > -std::numeric_limits<double>::infinity(),
            "sim: no clear walking path for person " + std::to_string(i) + " in scene " + scene.name);
    out.push_back(best);
  }
  return out;
}

std::vector<Primitive> walker_primitives(const Walker& w, double t_s) {
  const Eigen::Vector2d p = w.position(t_s);
  SE3 T_w_o = SE3::Identity();
  T_w_o.translate(Eigen::Vector3d(p.x(), p.y(), 0.0));
  T_w_o.rotate(Eigen::AngleAxisd(w.heading_rad(t_s), Eigen::Vector3d::UnitZ()));
  const double r = w.radius_m, head = 0.11, shoulder = w.height_m - 2 * head - 0.05;
  auto part = [&](Shape shape, double z, const Eigen::Vector3d& half, const Material& m) {
    Primitive prim;
    prim.shape = shape;
    prim.T_w_p = T_w_o;
    prim.T_w_p.translate(Eigen::Vector3d(0, 0, z));
    prim.half_extents_m = half;
    prim.material = m;
    prim.label = cls::kPerson;
    return prim;
  };
  // A capsule (cylinder between two spheres) from the floor to the shoulders, and a head.
  const double half_body = 0.5 * (shoulder - 2 * r);
  return {part(Shape::kSphere, r, {r, r, r}, w.clothes),
          part(Shape::kCylinder, r + half_body, {r, r, half_body}, w.clothes),
          part(Shape::kSphere, shoulder - r, {r, r, r}, w.clothes),
          part(Shape::kSphere, w.height_m - head, {head, head, head}, w.skin)};
}

}  // namespace s3m::sim
