#include "s3m/sim/furniture.hpp"

#include <cmath>

namespace s3m::sim {
namespace {

using V3 = Eigen::Vector3d;
using C3 = Eigen::Vector3f;

const Material kMetalDark = mat(Pattern::kMetal, {0.18f, 0.18f, 0.2f}, {0.1f, 0.1f, 0.1f}, 0.1f);
const Material kMetalLight = mat(Pattern::kMetal, {0.6f, 0.6f, 0.62f}, {0.4f, 0.4f, 0.4f}, 0.1f);
const Material kWoodLight = mat(Pattern::kWood, {0.72f, 0.52f, 0.32f}, {0.5f, 0.32f, 0.16f}, 0.25f);
const Material kWoodDark = mat(Pattern::kWood, {0.42f, 0.26f, 0.14f}, {0.25f, 0.14f, 0.07f}, 0.2f);

}  // namespace

Material mat(Pattern p, const Eigen::Vector3f& base, const Eigen::Vector3f& accent, float scale_m) {
  Material m;
  m.pattern = p;
  m.base = base;
  m.accent = accent;
  m.scale_m = scale_m;
  return m;
}

Material SceneBuilder::jitter(Material m) {
  const float k = static_cast<float>(rng_.uniform(0.9, 1.1));
  const C3 tint(static_cast<float>(rng_.uniform(0.93, 1.07)), static_cast<float>(rng_.uniform(0.93, 1.07)),
                static_cast<float>(rng_.uniform(0.93, 1.07)));
  m.base = (m.base.cwiseProduct(tint) * k).cwiseMin(1.0f);
  m.accent = (m.accent * k).cwiseMin(1.0f);
  m.seed = static_cast<std::uint32_t>(rng_.next());
  return m;
}

int SceneBuilder::object(const std::string& kind, ClassId label) {
  return scene_.add_object(kind + "_" + std::to_string(counter_++), label);
}

void SceneBuilder::box(int obj, const SE3& T_w_o, const V3& centre_o, const V3& half_m, const Material& m) {
  SE3 T_o_p = SE3::Identity();
  T_o_p.translation() = centre_o;
  scene_.add_primitive(obj, Shape::kBox, T_w_o * T_o_p, half_m, m);
}

void SceneBuilder::cylinder(int obj, const SE3& T_w_o, const V3& centre_o, double radius_m, double half_height_m,
                            const Material& m) {
  SE3 T_o_p = SE3::Identity();
  T_o_p.translation() = centre_o;
  scene_.add_primitive(obj, Shape::kCylinder, T_w_o * T_o_p, V3(radius_m, radius_m, half_height_m), m);
}

void SceneBuilder::sphere(int obj, const SE3& T_w_o, const V3& centre_o, double radius_m, const Material& m) {
  SE3 T_o_p = SE3::Identity();
  T_o_p.translation() = centre_o;
  scene_.add_primitive(obj, Shape::kSphere, T_w_o * T_o_p, V3(radius_m, radius_m, radius_m), m);
}

SE3 SceneBuilder::floor_frame(double x_m, double y_m, double yaw_rad) {
  SE3 T = SE3::Identity();
  T.linear() = Eigen::AngleAxisd(yaw_rad, V3::UnitZ()).toRotationMatrix();
  T.translation() = V3(x_m, y_m, 0.0);
  return T;
}

SE3 SceneBuilder::wall_frame(int wall, double along_m, double off_wall_m) const {
  const V3 lo = scene_.room.min, hi = scene_.room.max;
  switch (wall) {
    case 0: return floor_frame(lo.x() + along_m, lo.y() + off_wall_m, 0.0);
    case 1: return floor_frame(hi.x() - off_wall_m, lo.y() + along_m, M_PI / 2);
    case 2: return floor_frame(hi.x() - along_m, hi.y() - off_wall_m, M_PI);
    default: return floor_frame(lo.x() + off_wall_m, hi.y() - along_m, -M_PI / 2);
  }
}

void SceneBuilder::room(const V3& size_m, const Material& wall, const Material& floor, const Material& ceiling) {
  scene_.room.min = V3::Zero();
  scene_.room.max = size_m;
  const double t = 0.1, X = size_m.x(), Y = size_m.y(), Z = size_m.z();
  const SE3 I = SE3::Identity();
  box(object("floor", cls::kFloor), I, V3(X / 2, Y / 2, -t / 2), V3(X / 2 + t, Y / 2 + t, t / 2), floor);
  box(object("ceiling", cls::kCeiling), I, V3(X / 2, Y / 2, Z + t / 2), V3(X / 2 + t, Y / 2 + t, t / 2), ceiling);
  const int w = object("wall", cls::kWall);
  box(w, I, V3(X / 2, -t / 2, Z / 2), V3(X / 2 + t, t / 2, Z / 2), jitter(wall));
  box(w, I, V3(X / 2, Y + t / 2, Z / 2), V3(X / 2 + t, t / 2, Z / 2), jitter(wall));
  box(w, I, V3(-t / 2, Y / 2, Z / 2), V3(t / 2, Y / 2, Z / 2), jitter(wall));
  box(w, I, V3(X + t / 2, Y / 2, Z / 2), V3(t / 2, Y / 2, Z / 2), jitter(wall));
}

void SceneBuilder::door(const SE3& T) {
  const int o = object("door", cls::kDoor);
  Material m = jitter(rng_.chance(0.5) ? mat(Pattern::kPanel, {0.75f, 0.6f, 0.42f}, {0.55f, 0.4f, 0.25f}, 0.3f)
                                       : mat(Pattern::kPanel, {0.85f, 0.85f, 0.82f}, {0.6f, 0.6f, 0.58f}, 0.5f));
  box(o, T, V3(0, 0.02, 1.025), V3(0.45, 0.02, 1.025), m);
  box(o, T, V3(0, 0.005, 1.06), V3(0.52, 0.005, 1.06), jitter(kMetalLight));  // frame (casing)
}

void SceneBuilder::window(const SE3& T, double width_m, double height_m, double sill_m) {
  const int o = object("window", cls::kWindow);
  box(o, T, V3(0, 0.015, sill_m + height_m / 2), V3(width_m / 2, 0.015, height_m / 2),
      jitter(mat(Pattern::kSky, {0.45f, 0.62f, 0.9f}, {0.92f, 0.92f, 0.9f}, 1.0f)));
}

void SceneBuilder::poster(const SE3& T, double width_m, double height_m, double centre_z_m) {
  const int o = object("poster", cls::kOther);
  const C3 bg = rng_.chance(0.5) ? C3(0.92f, 0.9f, 0.85f) : C3(0.2f, 0.25f, 0.35f);
  box(o, T, V3(0, 0.008, centre_z_m), V3(width_m / 2, 0.008, height_m / 2),
      jitter(mat(Pattern::kPoster, bg, {0.1f, 0.1f, 0.1f}, static_cast<float>(rng_.uniform(0.08, 0.16)))));
}

void SceneBuilder::table(const SE3& T, double w, double d, double h) {
  const int o = object("table", cls::kTable);
  const Material top = jitter(rng_.chance(0.6) ? kWoodLight : kWoodDark);
  const Material leg = jitter(rng_.chance(0.5) ? kMetalDark : kMetalLight);
  box(o, T, V3(0, 0, h - 0.015), V3(w / 2, d / 2, 0.015), top);
  for (int sx : {-1, 1})
    for (int sy : {-1, 1}) box(o, T, V3(sx * (w / 2 - 0.05), sy * (d / 2 - 0.05), (h - 0.03) / 2), V3(0.02, 0.02, (h - 0.03) / 2), leg);
}

void SceneBuilder::chair(const SE3& T) {
  const int o = object("chair", cls::kChair);
  const C3 c = rng_.chance(0.5) ? C3(0.15f, 0.2f, 0.45f) : C3(0.5f, 0.12f, 0.1f);
  const Material seat = jitter(mat(Pattern::kFabric, c, c * 0.6f, 0.05f));
  const Material leg = jitter(kMetalDark);
  box(o, T, V3(0, 0, 0.45), V3(0.22, 0.22, 0.03), seat);
  box(o, T, V3(0, -0.2, 0.72), V3(0.22, 0.025, 0.22), seat);
  for (int sx : {-1, 1})
    for (int sy : {-1, 1}) box(o, T, V3(sx * 0.19, sy * 0.19, 0.21), V3(0.015, 0.015, 0.21), leg);
}

void SceneBuilder::sofa(const SE3& T, double w) {
  const int o = object("sofa", cls::kSofa);
  const C3 c = rng_.chance(0.5) ? C3(0.35f, 0.38f, 0.42f) : C3(0.55f, 0.42f, 0.3f);
  const Material m = jitter(mat(Pattern::kFabric, c, c * 0.7f, 0.5f));
  box(o, T, V3(0, 0.05, 0.22), V3(w / 2 - 0.12, 0.4, 0.22), m);                       // seat
  box(o, T, V3(0, -0.35, 0.45), V3(w / 2, 0.12, 0.45), m);                            // back
  for (int s : {-1, 1}) box(o, T, V3(s * (w / 2 - 0.06), 0.05, 0.32), V3(0.06, 0.4, 0.32), m);  // arms
  box(o, T, V3(-w / 4, 0.0, 0.5), V3(0.2, 0.07, 0.06), jitter(mat(Pattern::kFabric, {0.8f, 0.6f, 0.2f}, {0.5f, 0.3f, 0.1f}, 0.05f)));
}

void SceneBuilder::bed(const SE3& T) {
  const int o = object("bed", cls::kBed);
  box(o, T, V3(0, 0, 0.15), V3(0.8, 1.05, 0.15), jitter(kWoodDark));                  // frame
  box(o, T, V3(0, 0.02, 0.4), V3(0.76, 1.0, 0.1), jitter(mat(Pattern::kFabric, {0.9f, 0.9f, 0.88f}, {0.8f, 0.8f, 0.8f}, 0.3f)));
  box(o, T, V3(0, 0.3, 0.52), V3(0.78, 0.72, 0.03), jitter(mat(Pattern::kFabric, {0.3f, 0.5f, 0.4f}, {0.8f, 0.75f, 0.6f}, 0.15f)));
  box(o, T, V3(0, -0.82, 0.56), V3(0.6, 0.15, 0.06), jitter(mat(Pattern::kFabric, {0.95f, 0.95f, 0.95f}, {0.85f, 0.85f, 0.9f}, 0.1f)));
  box(o, T, V3(0, -1.07, 0.5), V3(0.8, 0.03, 0.5), jitter(mat(Pattern::kPanel, {0.42f, 0.26f, 0.14f}, {0.25f, 0.14f, 0.07f}, 0.2f)));
}

void SceneBuilder::cabinet(const SE3& T, double w, double h) {
  const int o = object("cabinet", cls::kCabinet);
  const Material m = jitter(rng_.chance(0.5) ? mat(Pattern::kPanel, {0.85f, 0.83f, 0.78f}, {0.6f, 0.58f, 0.55f}, 0.5f)
                                             : mat(Pattern::kPanel, {0.7f, 0.5f, 0.3f}, {0.5f, 0.32f, 0.16f}, 0.3f));
  const int doors = w > 0.7 ? 2 : 1;
  box(o, T, V3(0, 0, h / 2), V3(w / 2, 0.22, h / 2), m);
  for (int i = 0; i < doors; ++i) {
    const double dw = w / doors, x = -w / 2 + dw * (i + 0.5);
    box(o, T, V3(x, 0.23, h / 2), V3(dw / 2 - 0.01, 0.01, h / 2 - 0.02), m);
    box(o, T, V3(x + (i == 0 && doors == 2 ? dw / 2 - 0.06 : -dw / 2 + 0.06), 0.25, h / 2), V3(0.01, 0.01, 0.08), kMetalLight);
  }
}

void SceneBuilder::shelf(const SE3& T, double w, double h, int levels) {
  const int o = object("shelf", cls::kShelf);
  const Material wood = jitter(rng_.chance(0.5) ? kWoodLight : kWoodDark);
  const double d = 0.17, t = 0.01;  // half depth, half board thickness
  for (int s : {-1, 1}) box(o, T, V3(s * (w / 2 - t), 0, h / 2), V3(t, d, h / 2), wood);
  box(o, T, V3(0, -d + t, h / 2), V3(w / 2, t, h / 2), wood);  // back board
  const double step = (h - 2 * t) / levels;
  for (int i = 0; i <= levels; ++i) box(o, T, V3(0, 0, t + i * step), V3(w / 2 - 2 * t, d, t), wood);
  for (int i = 0; i < levels; ++i) {
    if (rng_.chance(0.15)) continue;  // an empty compartment now and then
    Material books = jitter(mat(Pattern::kBooks, {0.5f, 0.5f, 0.5f}, {0.3f, 0.25f, 0.2f}, static_cast<float>(step - 4 * t)));
    const double bh = (step - 4 * t) / 2;
    box(o, T, V3(0, 0.0, 2 * t + i * step + bh), V3(w / 2 - 3 * t, d - 0.04, bh), books);
  }
}

void SceneBuilder::monitor(const SE3& T, double base_z, double w, double h, bool is_tv) {
  const int o = object(is_tv ? "tv" : "monitor", cls::kTvMonitor);
  const C3 desk = rng_.chance(0.5) ? C3(0.15f, 0.35f, 0.6f) : C3(0.3f, 0.5f, 0.3f);
  const double stand = is_tv ? 0.08 : 0.12;
  cylinder(o, T, V3(0, -0.02, base_z + stand / 2), 0.025, stand / 2, kMetalDark);
  box(o, T, V3(0, -0.02, base_z + 0.006), V3(0.12, 0.08, 0.006), kMetalDark);
  box(o, T, V3(0, 0, base_z + stand + h / 2), V3(w / 2, 0.02, h / 2),
      jitter(mat(Pattern::kScreen, desk, {0.05f, 0.05f, 0.05f}, 0.1f)));
}

void SceneBuilder::plant(const SE3& T, double height_m) {
  const int o = object("plant", cls::kPlant);
  cylinder(o, T, V3(0, 0, 0.15), 0.15, 0.15, jitter(mat(Pattern::kPaint, {0.6f, 0.3f, 0.18f}, {0.4f, 0.2f, 0.1f}, 0.05f)));
  const Material leaves = jitter(mat(Pattern::kFoliage, {0.1f, 0.4f, 0.1f}, {0.25f, 0.55f, 0.12f}, 0.05f));
  const double r = 0.2 + 0.1 * height_m;
  sphere(o, T, V3(0, 0, height_m - r), r, leaves);
  sphere(o, T, V3(0.12, 0.05, height_m - 1.7 * r), 0.7 * r, leaves);
  sphere(o, T, V3(-0.1, -0.06, height_m - 1.9 * r), 0.65 * r, leaves);
}

void SceneBuilder::person(const SE3& T, double height_m) {
  const int o = object("person", cls::kPerson);
  const double s = height_m / 1.75;
  const C3 shirt = rng_.chance(0.5) ? C3(0.7f, 0.15f, 0.15f) : C3(0.2f, 0.45f, 0.25f);
  const Material trousers = jitter(mat(Pattern::kFabric, {0.12f, 0.15f, 0.3f}, {0.08f, 0.1f, 0.2f}, 0.1f));
  const Material top = jitter(mat(Pattern::kFabric, shirt, shirt * 0.6f, 0.08f));
  const Material skin = jitter(mat(Pattern::kPaint, {0.8f, 0.6f, 0.48f}, {0.7f, 0.5f, 0.4f}, 0.05f));
  for (int side : {-1, 1}) {
    cylinder(o, T, V3(side * 0.1 * s, 0, 0.43 * s), 0.07 * s, 0.43 * s, trousers);
    cylinder(o, T, V3(side * 0.25 * s, 0, 1.15 * s), 0.045 * s, 0.3 * s, top);
  }
  box(o, T, V3(0, 0, 1.17 * s), V3(0.2 * s, 0.12 * s, 0.3 * s), top);
  cylinder(o, T, V3(0, 0, 1.5 * s), 0.05 * s, 0.05 * s, skin);
  sphere(o, T, V3(0, 0, 1.64 * s), 0.11 * s, skin);
}

}  // namespace s3m::sim
