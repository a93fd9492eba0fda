#pragma once
// Embree 3 wrapper: the scene's primitives tessellated into one triangle geometry each
// (geometry id == primitive index), intersected with 8-wide ray packets.
#include <memory>

#include <Eigen/Core>

#include "s3m/sim/scene.hpp"

namespace s3m::sim {

inline constexpr int kPacket = 8;  // rays per packet (AVX2 width)

// One packet of rays: origins and directions in world coordinates [m]; after intersect(),
// t_hit is the ray parameter of the nearest hit (infinity = miss), prim the primitive index
// (-1 = miss).
struct RayPacket {
  alignas(32) float ox[kPacket], oy[kPacket], oz[kPacket];
  alignas(32) float dx[kPacket], dy[kPacket], dz[kPacket];
  alignas(32) float t_max[kPacket];
  alignas(32) int active[kPacket];  // -1 = trace, 0 = ignore
  alignas(32) float t_hit[kPacket];
  alignas(32) int prim[kPacket];
};

class Raycaster {
 public:
  explicit Raycaster(const Scene& scene);
  ~Raycaster();
  Raycaster(const Raycaster&) = delete;
  Raycaster& operator=(const Raycaster&) = delete;
  Raycaster(Raycaster&&) noexcept;
  Raycaster& operator=(Raycaster&&) noexcept;

  // Thread-safe: many threads may intersect concurrently.
  void intersect(RayPacket& packet) const;
  std::size_t triangle_count() const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

// Triangle mesh of a primitive in world coordinates (exposed for tests and the voxeliser).
struct TriMesh {
  std::vector<Eigen::Vector3f> vertices_w;
  std::vector<Eigen::Vector3i> triangles;
};
TriMesh tessellate(const Primitive& prim);

}  // namespace s3m::sim
