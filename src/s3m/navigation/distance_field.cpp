#include "s3m/navigation/distance_field.hpp"

#include <algorithm>
#include <cmath>

#include <dynamicEDT3D/dynamicEDTOctomap.h>

#include "s3m/core/error.hpp"

namespace s3m::navigation {

struct DistanceField::Edt : DynamicEDTOctomapBase<mapping::SemanticOcTree> {
  using DynamicEDTOctomapBase::DynamicEDTOctomapBase;
};

UnknownSpace unknown_space_from_string(const std::string& name) {
  if (name == "occupied") return UnknownSpace::kOccupied;
  if (name == "free") return UnknownSpace::kFree;
  throw Error("unknown-space policy '" + name + "' (expected 'occupied' or 'free')");
}

std::string to_string(UnknownSpace u) { return u == UnknownSpace::kOccupied ? "occupied" : "free"; }

void DistanceFieldConfig::validate() const {
  require(std::isfinite(max_distance_m) && max_distance_m > 0.0,
          "distance field: max_distance_m must be > 0 (got " + std::to_string(max_distance_m) + ")");
}

DistanceField::DistanceField(mapping::SemanticOcTree& tree, const DistanceFieldConfig& cfg)
    : tree_(tree), cfg_(cfg), resolution_(tree.getResolution()) {
  cfg_.validate();
  require(tree.size() > 0, "distance field: the map has no known voxels");
  // The box of the map's known leaves, from the centre of the first voxel to that of the last.
  double x0, y0, z0, x1, y1, z1;
  tree.getMetricMin(x0, y0, z0);
  tree.getMetricMax(x1, y1, z1);
  const double h = 0.5 * resolution_;
  octomap::OcTreeKey k0 = tree.coordToKey(x0 + h, y0 + h, z0 + h);
  octomap::OcTreeKey k1 = tree.coordToKey(x1 - h, y1 - h, z1 - h);
  // Unknown space counted as occupied: one more voxel all round, unknown by construction, stands
  // for everything outside the map, so distances near the edge see it.
  if (cfg_.unknown == UnknownSpace::kOccupied)
    for (int i = 0; i < 3; ++i) --k0[i], ++k1[i];
  const octomap::point3d c0 = tree.keyToCoord(k0), c1 = tree.keyToCoord(k1);
  min_w_ = {c0.x(), c0.y(), c0.z()};
  max_w_ = {c1.x(), c1.y(), c1.z()};
  edt_ = std::make_unique<Edt>(float(cfg_.max_distance_m), &tree, c0, c1,
                               cfg_.unknown == UnknownSpace::kOccupied);
  edt_->update();
}

DistanceField::~DistanceField() = default;

void DistanceField::update() { edt_->update(); }

bool DistanceField::contains(const Eigen::Vector3d& p_w) const {
  const double h = 0.5 * resolution_;
  return (p_w.array() >= min_w_.array() - h).all() && (p_w.array() < max_w_.array() + h).all();
}

double DistanceField::clearance(const Eigen::Vector3d& p_w) const {
  if (!contains(p_w)) return cfg_.unknown == UnknownSpace::kOccupied ? 0.0 : cfg_.max_distance_m;
  const float d = edt_->getDistance(octomap::point3d(float(p_w.x()), float(p_w.y()), float(p_w.z())));
  if (d < 0.0f) return cfg_.unknown == UnknownSpace::kOccupied ? 0.0 : cfg_.max_distance_m;  // edge rounding
  return std::min(double(d), cfg_.max_distance_m);
}

}  // namespace s3m::navigation
