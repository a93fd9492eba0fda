#include "s3m/sim/scene.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

#include "s3m/core/error.hpp"

namespace s3m::sim {

int Scene::add_object(const std::string& object_name, ClassId label) {
  objects.push_back({object_name, label});
  return static_cast<int>(objects.size()) - 1;
}

void Scene::add_primitive(int object_id, Shape shape, const SE3& T_w_p, const Eigen::Vector3d& half_extents_m,
                          const Material& material) {
  require(object_id >= 0 && object_id < static_cast<int>(objects.size()),
          "Scene::add_primitive: object id " + std::to_string(object_id) + " does not exist");
  require((half_extents_m.array() > 0).all(), "Scene::add_primitive: half extents must be positive (object '" +
                                                  objects[object_id].name + "')");
  Primitive p;
  p.shape = shape;
  p.T_w_p = T_w_p;
  p.half_extents_m = half_extents_m;
  p.material = material;
  p.label = objects[object_id].label;
  p.object_id = object_id;
  primitives.push_back(p);
}

double signed_distance_m(const Primitive& prim, const Eigen::Vector3d& p_w) {
  const Eigen::Vector3d p = prim.T_w_p.inverse() * p_w;
  const Eigen::Vector3d& h = prim.half_extents_m;
  switch (prim.shape) {
    case Shape::kBox: {
      const Eigen::Vector3d q = p.cwiseAbs() - h;
      return q.cwiseMax(0.0).norm() + std::min(q.maxCoeff(), 0.0);
    }
    case Shape::kCylinder: {
      const Eigen::Vector2d d(p.head<2>().norm() - h.x(), std::abs(p.z()) - h.z());
      return d.cwiseMax(0.0).norm() + std::min(d.maxCoeff(), 0.0);
    }
    case Shape::kSphere:
      return p.norm() - h.x();
  }
  return std::numeric_limits<double>::infinity();
}

double Scene::clearance_m(const Eigen::Vector3d& p_w) const {
  double d = std::numeric_limits<double>::infinity();
  for (const auto& prim : primitives) {
    if (prim.label == cls::kWall || prim.label == cls::kFloor || prim.label == cls::kCeiling) continue;
    d = std::min(d, signed_distance_m(prim, p_w));
  }
  // The room shell counts too: distance to the nearest inner face of the room box.
  const Eigen::Vector3d lo = p_w - room.min, hi = room.max - p_w;
  return std::min(d, std::min(lo.minCoeff(), hi.minCoeff()));
}

}  // namespace s3m::sim
