#pragma once
// Furniture and room parts composed from primitives. Every builder takes the object's floor frame
// T_w_o: origin on the floor at the centre of the footprint, x along the object's width, y towards
// its front (the side a person uses: shelf openings, screen, seat), z up. Sizes are metres.
#include <string>

#include "s3m/sim/rng.hpp"
#include "s3m/sim/scene.hpp"

namespace s3m::sim {

class SceneBuilder {
 public:
  SceneBuilder(Scene& scene, Rng& rng) : scene_(scene), rng_(rng) {}

  // Room shell: floor, ceiling and four walls around [0, size] with wall thickness outside it,
  // plus a ceiling light per entry of light_xy.
  void room(const Eigen::Vector3d& size_m, const Material& wall, const Material& floor, const Material& ceiling);

  // Frame on the inner face of wall w (0: y=0, 1: x=max, 2: y=max, 3: x=0) at distance along_m
  // from the wall's left end (seen from inside), with y pointing into the room.
  SE3 wall_frame(int wall, double along_m, double off_wall_m = 0.0) const;
  // Frame at floor position (x, y) [m] with yaw [rad] (object front = +y rotated by yaw).
  static SE3 floor_frame(double x_m, double y_m, double yaw_rad);

  void door(const SE3& T_w_o);
  void window(const SE3& T_w_o, double width_m, double height_m, double sill_m);
  void poster(const SE3& T_w_o, double width_m, double height_m, double centre_z_m);
  void table(const SE3& T_w_o, double width_m, double depth_m, double height_m);
  void chair(const SE3& T_w_o);
  void sofa(const SE3& T_w_o, double width_m);
  void bed(const SE3& T_w_o);
  void cabinet(const SE3& T_w_o, double width_m, double height_m);
  void shelf(const SE3& T_w_o, double width_m, double height_m, int levels);
  // Screen standing on a surface at height base_z_m (monitor on a desk, TV on a cabinet).
  void monitor(const SE3& T_w_o, double base_z_m, double width_m, double height_m, bool is_tv);
  void plant(const SE3& T_w_o, double height_m);
  void person(const SE3& T_w_o, double height_m);

  // Random helpers for layouts.
  Rng& rng() { return rng_; }
  Material jitter(Material m);  // varies colours by +-10% and picks a new pattern seed

 private:
  int object(const std::string& kind, ClassId label);
  void box(int obj, const SE3& T_w_o, const Eigen::Vector3d& centre_o, const Eigen::Vector3d& half_m, const Material& m);
  void cylinder(int obj, const SE3& T_w_o, const Eigen::Vector3d& centre_o, double radius_m, double half_height_m,
                const Material& m);
  void sphere(int obj, const SE3& T_w_o, const Eigen::Vector3d& centre_o, double radius_m, const Material& m);

  Scene& scene_;
  Rng& rng_;
  int counter_ = 0;
};

// Ready-made materials (colours in linear RGB).
Material mat(Pattern p, const Eigen::Vector3f& base, const Eigen::Vector3f& accent, float scale_m);

}  // namespace s3m::sim
