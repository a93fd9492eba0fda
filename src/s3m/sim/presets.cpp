// Scene presets. Layouts put furniture along the walls and keep a central flight zone clear, so
// every trajectory sees furniture, posters, doors and windows rather than blank walls. The seed
// jitters room size, positions along walls, colours and patterns.
#include <cmath>

#include "s3m/core/error.hpp"
#include "s3m/sim/furniture.hpp"

namespace s3m::sim {
namespace {

using V3 = Eigen::Vector3d;

SE3 turned(const SE3& T, double yaw_rad) {
  SE3 R = SE3::Identity();
  R.linear() = Eigen::AngleAxisd(yaw_rad, V3::UnitZ()).toRotationMatrix();
  return T * R;
}

void common_shell(SceneBuilder& b, Scene& s, const V3& size, Pattern floor_pattern) {
  const Material wall = mat(Pattern::kPaint, {0.82f, 0.8f, 0.74f}, {0.62f, 0.6f, 0.55f}, 0.35f);
  const Material floor = floor_pattern == Pattern::kWood
                             ? mat(Pattern::kWood, {0.62f, 0.45f, 0.28f}, {0.42f, 0.28f, 0.15f}, 0.18f)
                         : floor_pattern == Pattern::kCarpet
                             ? mat(Pattern::kCarpet, {0.3f, 0.32f, 0.38f}, {0.45f, 0.4f, 0.35f}, 0.3f)
                             : mat(Pattern::kTiles, {0.7f, 0.68f, 0.62f}, {0.35f, 0.33f, 0.3f}, 0.4f);
  const Material ceiling = mat(Pattern::kTiles, {0.9f, 0.9f, 0.88f}, {0.6f, 0.6f, 0.6f}, 0.6f);
  b.room(size, wall, b.jitter(floor), b.jitter(ceiling));
  s.lights = {{V3(size.x() / 3, size.y() / 2, size.z() - 0.05), 1.0f},
              {V3(2 * size.x() / 3, size.y() / 2, size.z() - 0.05), 0.8f}};
}

double j(Rng& r, double amount) { return r.uniform(-amount, amount); }

Scene office(std::uint64_t seed) {
  Scene s;
  s.name = "office";
  Rng rng(seed);
  SceneBuilder b(s, rng);
  const V3 size(7.0 + j(rng, 0.3), 5.0 + j(rng, 0.2), 2.8);
  common_shell(b, s, size, rng.chance(0.5) ? Pattern::kCarpet : Pattern::kTiles);
  const double X = size.x(), Y = size.y();
  // Wall 0: door and two desks with monitors and chairs, posters above.
  b.door(b.wall_frame(0, 0.9 + j(rng, 0.15)));
  for (double along : {3.0, 5.3}) {
    const SE3 T = b.wall_frame(0, along + j(rng, 0.15), 0.37);
    b.table(T, 1.4, 0.7, 0.74);
    b.monitor(turned(T, 0.0) * SE3(Eigen::Translation3d(0.1, -0.1, 0)), 0.74, 0.56, 0.34, false);
    b.chair(turned(T * SE3(Eigen::Translation3d(j(rng, 0.2), 0.75, 0)), M_PI + j(rng, 0.4)));
    b.poster(b.wall_frame(0, along + j(rng, 0.3)), 0.6, 0.8, 1.75);
  }
  // Wall 1: window, plant, cabinet.
  b.plant(b.wall_frame(1, 0.5, 0.35), 1.2 + j(rng, 0.2));
  b.window(b.wall_frame(1, Y / 2 + j(rng, 0.3)), 1.5, 1.2, 0.9);
  b.cabinet(b.wall_frame(1, Y - 0.7, 0.23), 0.8, 1.1);
  // Wall 2: two bookshelves, a cabinet with a poster, a sofa.
  b.shelf(b.wall_frame(2, 0.8, 0.18), 0.9, 1.9, 5);
  b.shelf(b.wall_frame(2, 1.8 + j(rng, 0.05), 0.18), 0.9, 1.6, 4);
  b.cabinet(b.wall_frame(2, 3.1 + j(rng, 0.1), 0.23), 0.9, 0.8);
  b.poster(b.wall_frame(2, 3.1), 0.9, 0.6, 1.55);
  b.sofa(b.wall_frame(2, X - 1.6 + j(rng, 0.2), 0.47), 1.9);
  b.poster(b.wall_frame(2, X - 1.6), 1.0, 0.7, 1.7);
  // Wall 3: whiteboard-sized poster, a person, a plant, a window.
  b.poster(b.wall_frame(3, Y / 2 + 0.3), 1.5, 0.9, 1.45);
  b.person(b.wall_frame(3, 1.0 + j(rng, 0.2), 0.55) * SE3(Eigen::AngleAxisd(j(rng, 0.5), V3::UnitZ())),
           1.7 + j(rng, 0.1));
  b.plant(b.wall_frame(3, Y - 0.45, 0.35), 1.0 + j(rng, 0.2));
  s.flight_zone = {V3(1.5, 1.5, 0.3), V3(X - 1.5, Y - 1.5, 2.2)};
  return s;
}

Scene living_room(std::uint64_t seed) {
  Scene s;
  s.name = "living_room";
  Rng rng(seed);
  SceneBuilder b(s, rng);
  const V3 size(6.5 + j(rng, 0.2), 5.5 + j(rng, 0.2), 2.6);
  common_shell(b, s, size, Pattern::kWood);
  const double X = size.x(), Y = size.y();
  // Wall 0: door, TV on a low cabinet, plant.
  b.door(b.wall_frame(0, 1.0));
  const SE3 tv = b.wall_frame(0, 4.4 + j(rng, 0.2), 0.23);
  b.cabinet(tv, 1.4, 0.5);
  b.monitor(tv, 0.5, 1.1, 0.62, true);
  b.poster(b.wall_frame(0, 2.6), 0.7, 0.9, 1.6);
  b.plant(b.wall_frame(0, X - 0.45, 0.35), 1.3 + j(rng, 0.2));
  // Wall 1: shelf and window.
  b.shelf(b.wall_frame(1, 0.9, 0.18), 1.0, 1.8, 5);
  b.window(b.wall_frame(1, 3.2 + j(rng, 0.2)), 1.6, 1.3, 0.85);
  // Wall 2: sofa facing the TV, poster above it; coffee table and armchair in front.
  const SE3 sofa = b.wall_frame(2, X - 4.4, 0.47);
  b.sofa(sofa, 2.1);
  b.poster(b.wall_frame(2, X - 4.4 + j(rng, 0.2)), 1.2, 0.8, 1.65);
  b.table(b.floor_frame(4.4, Y / 2 - 0.1, j(rng, 0.1)), 1.0, 0.55, 0.45);
  b.chair(b.floor_frame(5.8, 1.9, M_PI / 2 + 0.4));
  // Wall 3: bed with the headboard against the wall, a person by the window side.
  b.bed(b.wall_frame(3, 1.3, 1.1));
  b.window(b.wall_frame(3, 3.5), 1.2, 1.2, 0.9);
  b.person(b.floor_frame(1.0, 1.2, 0.6 + j(rng, 0.3)), 1.65 + j(rng, 0.1));
  b.plant(b.floor_frame(0.4, 0.4, 0.0), 0.9);
  s.flight_zone = {V3(2.5, 1.4, 0.9), V3(X - 1.4, Y - 1.5, 2.0)};
  return s;
}

Scene corridor(std::uint64_t seed) {
  Scene s;
  s.name = "corridor";
  Rng rng(seed);
  SceneBuilder b(s, rng);
  const V3 size(12.0 + j(rng, 0.5), 2.4, 2.6);
  common_shell(b, s, size, Pattern::kTiles);
  s.lights = {{V3(2, 1.2, 2.55), 0.8f}, {V3(6, 1.2, 2.55), 0.8f}, {V3(10, 1.2, 2.55), 0.8f}};
  const double X = size.x();
  for (double along : {2.0, 6.0, 10.0}) b.door(b.wall_frame(0, along + j(rng, 0.3)));
  for (double along : {3.5, 8.2}) b.door(b.wall_frame(2, along + j(rng, 0.3)));
  for (double along : {4.0, 8.0}) b.poster(b.wall_frame(0, along + j(rng, 0.3)), 0.7, 0.9, 1.5);
  for (double along : {1.5, 6.0, 10.3}) b.poster(b.wall_frame(2, along + j(rng, 0.3)), 0.8, 0.6, 1.55);
  b.cabinet(b.wall_frame(0, 5.0, 0.23), 0.7, 1.0);
  b.shelf(b.wall_frame(2, 5.0 + j(rng, 0.2), 0.18), 1.0, 1.8, 5);
  b.plant(b.wall_frame(0, 7.2, 0.3), 1.1);
  b.plant(b.wall_frame(2, X - 0.5, 0.3), 1.3);
  b.table(b.wall_frame(2, 1.0, 0.25), 0.8, 0.45, 0.75);
  b.person(b.wall_frame(0, 8.6 + j(rng, 0.3), 0.35), 1.75 + j(rng, 0.1));
  b.window(b.wall_frame(1, 1.2), 1.2, 1.3, 0.9);
  b.door(b.wall_frame(3, 1.2));
  s.flight_zone = {V3(1.2, 1.0, 0.5), V3(X - 1.2, 1.4, 1.9)};
  return s;
}

}  // namespace

std::vector<std::string> scene_presets() { return {"office", "living_room", "corridor"}; }

Scene make_scene(const std::string& preset, std::uint64_t seed) {
  if (preset == "office") return office(seed);
  if (preset == "living_room") return living_room(seed);
  if (preset == "corridor") return corridor(seed);
  throw Error("unknown scene preset '" + preset + "' (expected one of: office, living_room, corridor)");
}

}  // namespace s3m::sim
