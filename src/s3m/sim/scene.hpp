#pragma once
// A synthetic indoor scene: labelled primitives (boxes, cylinders, spheres) with procedural
// materials, point lights, and the free space a camera may fly through.
// World frame: x, y horizontal, z up, metres; the floor is z = 0.
#include <cstdint>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "s3m/core/classes.hpp"
#include "s3m/core/se3.hpp"

namespace s3m::sim {

// Procedural surface patterns (see texture.hpp). Each one has visible structure at several
// scales so that ORB corners exist at the distances a camera sees it from.
enum class Pattern : std::uint8_t {
  kPaint,     // wall paint: low-frequency blotches + fine speckle
  kWood,      // wood grain rings along the local x axis
  kTiles,     // square tiles with grout lines and per-tile colour jitter
  kCarpet,    // high-frequency fibre noise
  kFabric,    // woven cloth
  kBooks,     // shelf contents: vertical spines of random colours and heights
  kScreen,    // monitor/TV: dark bezel with bright application windows
  kPoster,    // random coloured rectangles, discs and text-like bars
  kSky,       // window glass: sky gradient with clouds and a horizon
  kFoliage,   // leaves
  kMetal,     // brushed metal
  kPanel,     // door / cabinet front: framed panels
};

struct Material {
  Pattern pattern = Pattern::kPaint;
  Eigen::Vector3f base{0.7f, 0.7f, 0.7f};    // albedo, linear RGB in [0, 1]
  Eigen::Vector3f accent{0.4f, 0.4f, 0.4f};  // second colour the pattern mixes in
  float scale_m = 0.2f;                      // characteristic feature size [m]
  std::uint32_t seed = 0;                    // per-object pattern variation
};

enum class Shape : std::uint8_t { kBox, kCylinder, kSphere };

// One primitive in its own frame p: a box centred at the origin with half extents,
// a cylinder along z (radius = half_extents.x, half height = half_extents.z), or a sphere
// (radius = half_extents.x).
struct Primitive {
  Shape shape = Shape::kBox;
  SE3 T_w_p = SE3::Identity();
  Eigen::Vector3d half_extents_m{0.5, 0.5, 0.5};
  Material material;
  ClassId label = cls::kUnknown;
  int object_id = -1;  // index into Scene::objects
};

// A semantic object (a table, a chair...) made of several primitives sharing one label.
struct SceneObject {
  std::string name;  // e.g. "table_2"
  ClassId label = cls::kUnknown;
};

struct PointLight {
  Eigen::Vector3d position_w{0, 0, 2.5};
  float intensity = 1.0f;  // diffuse gain at 1 m
};

struct Aabb {
  Eigen::Vector3d min{0, 0, 0}, max{0, 0, 0};
  bool contains(const Eigen::Vector3d& p, double margin = 0.0) const {
    return (p.array() >= min.array() + margin).all() && (p.array() <= max.array() - margin).all();
  }
  Eigen::Vector3d centre() const { return 0.5 * (min + max); }
  Eigen::Vector3d size() const { return max - min; }
};

struct Scene {
  std::string name;
  Aabb room;         // interior of the room (walls' inner faces) [m]
  Aabb flight_zone;  // where trajectories may place the robot: clear of furniture [m]
  std::vector<Primitive> primitives;
  std::vector<SceneObject> objects;
  std::vector<PointLight> lights;
  float ambient = 0.35f;

  // Adds an object and returns its id; primitives then reference it.
  int add_object(const std::string& name, ClassId label);
  void add_primitive(int object_id, Shape shape, const SE3& T_w_p, const Eigen::Vector3d& half_extents_m,
                     const Material& material);
  // Distance [m] from p to the nearest primitive surface that is not a room shell (wall, floor,
  // ceiling) -- positive outside, negative inside. Used to keep cameras out of furniture.
  double clearance_m(const Eigen::Vector3d& p_w) const;
};

// Signed distance [m] from a world point to a primitive's exact (untessellated) surface.
double signed_distance_m(const Primitive& prim, const Eigen::Vector3d& p_w);

// Scene presets: "office", "living_room", "corridor". The seed jitters positions, sizes, colours
// and patterns; seed 0 is as valid as any other. Throws s3m::Error for an unknown preset.
Scene make_scene(const std::string& preset, std::uint64_t seed);
std::vector<std::string> scene_presets();

}  // namespace s3m::sim
