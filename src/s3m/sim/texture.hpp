#pragma once
// Procedural textures: albedo as a pure function of the surface point in the primitive's own
// frame, so a surface looks the same from every view (features stay put for SLAM) and nothing
// has to be stored. Patterns mix smooth value noise (shading-like variation) with sharp edges
// (tiles, book spines, poster shapes) because ORB needs corners, not just gradients.
#include <Eigen/Core>

#include "s3m/sim/scene.hpp"

namespace s3m::sim {

// Albedo (linear RGB in [0, 1]) at point p_p [m] with unit normal n_p, both in the primitive
// frame; half_extents_m lets framed patterns (posters, doors, screens) fit the face.
Eigen::Vector3f albedo(const Material& m, Shape shape, const Eigen::Vector3f& half_extents_m,
                       const Eigen::Vector3f& p_p, const Eigen::Vector3f& n_p);

// Smooth 2-D value noise in [0, 1] (exposed for tests).
float value_noise(float x, float y, std::uint32_t seed);

}  // namespace s3m::sim
