#include "s3m/sim/raycaster.hpp"

#include <cmath>
#include <cstdlib>
#include <cstring>
#include <limits>
#include <string>

#include <embree3/rtcore.h>

#include "s3m/core/error.hpp"

namespace s3m::sim {
namespace {

constexpr int kCylinderSegments = 32;
constexpr int kSphereRings = 16, kSphereSegments = 32;

void box_mesh(const Eigen::Vector3d& h, std::vector<Eigen::Vector3d>& v, std::vector<Eigen::Vector3i>& f) {
  for (int i = 0; i < 8; ++i)
    v.emplace_back((i & 1) ? h.x() : -h.x(), (i & 2) ? h.y() : -h.y(), (i & 4) ? h.z() : -h.z());
  // Faces wound counter-clockwise seen from outside.
  const int quads[6][4] = {{0, 2, 3, 1}, {4, 5, 7, 6}, {0, 1, 5, 4},
                           {2, 6, 7, 3}, {0, 4, 6, 2}, {1, 3, 7, 5}};
  for (const auto& q : quads) {
    f.emplace_back(q[0], q[1], q[2]);
    f.emplace_back(q[0], q[2], q[3]);
  }
}

void cylinder_mesh(const Eigen::Vector3d& h, std::vector<Eigen::Vector3d>& v,
                   std::vector<Eigen::Vector3i>& f) {
  const int n = kCylinderSegments;
  for (int i = 0; i < n; ++i) {
    const double a = 2 * M_PI * i / n;
    v.emplace_back(h.x() * std::cos(a), h.x() * std::sin(a), -h.z());
    v.emplace_back(h.x() * std::cos(a), h.x() * std::sin(a), h.z());
  }
  const int bottom = static_cast<int>(v.size()), top = bottom + 1;
  v.emplace_back(0, 0, -h.z());
  v.emplace_back(0, 0, h.z());
  for (int i = 0; i < n; ++i) {
    const int a0 = 2 * i, a1 = a0 + 1, b0 = 2 * ((i + 1) % n), b1 = b0 + 1;
    f.emplace_back(a0, b0, b1);
    f.emplace_back(a0, b1, a1);
    f.emplace_back(bottom, b0, a0);
    f.emplace_back(top, a1, b1);
  }
}

void sphere_mesh(double r, std::vector<Eigen::Vector3d>& v, std::vector<Eigen::Vector3i>& f) {
  const int R = kSphereRings, S = kSphereSegments;
  for (int i = 0; i <= R; ++i) {
    const double th = M_PI * i / R;
    for (int k = 0; k < S; ++k) {
      const double ph = 2 * M_PI * k / S;
      v.emplace_back(r * std::sin(th) * std::cos(ph), r * std::sin(th) * std::sin(ph), r * std::cos(th));
    }
  }
  for (int i = 0; i < R; ++i)
    for (int k = 0; k < S; ++k) {
      const int a = i * S + k, b = i * S + (k + 1) % S, c = (i + 1) * S + k, d = (i + 1) * S + (k + 1) % S;
      f.emplace_back(a, c, d);
      f.emplace_back(a, d, b);
    }
}

}  // namespace

TriMesh tessellate(const Primitive& prim) {
  std::vector<Eigen::Vector3d> v;
  TriMesh mesh;
  switch (prim.shape) {
    case Shape::kBox: box_mesh(prim.half_extents_m, v, mesh.triangles); break;
    case Shape::kCylinder: cylinder_mesh(prim.half_extents_m, v, mesh.triangles); break;
    case Shape::kSphere: sphere_mesh(prim.half_extents_m.x(), v, mesh.triangles); break;
  }
  mesh.vertices_w.reserve(v.size());
  for (const auto& p : v) mesh.vertices_w.push_back((prim.T_w_p * p).cast<float>());
  return mesh;
}

struct Raycaster::Impl {
  RTCDevice device = nullptr;
  RTCScene scene = nullptr;
  std::size_t triangles = 0;
  ~Impl() {
    if (scene) rtcReleaseScene(scene);
    if (device) rtcReleaseDevice(device);
  }
};

Raycaster::Raycaster(const Scene& scene) : impl_(std::make_unique<Impl>()) {
  // S3M_EMBREE_CONFIG (e.g. "isa=sse4.2") pins Embree's kernels, whose choice otherwise follows the
  // CPU: the test suite runs with it to show that no test depends on the machine's SIMD width.
  const char* config = std::getenv("S3M_EMBREE_CONFIG");
  impl_->device = rtcNewDevice(config);
  if (!impl_->device)
    throw Error("Embree: rtcNewDevice(\"" + std::string(config ? config : "") + "\") failed (error " +
                std::to_string(rtcGetDeviceError(nullptr)) + ")");
  impl_->scene = rtcNewScene(impl_->device);
  // Robust mode: no cracks along shared triangle edges (otherwise stray rays pass between faces).
  rtcSetSceneFlags(impl_->scene, RTC_SCENE_FLAG_ROBUST);
  rtcSetSceneBuildQuality(impl_->scene, RTC_BUILD_QUALITY_HIGH);
  for (std::size_t i = 0; i < scene.primitives.size(); ++i) {
    const TriMesh mesh = tessellate(scene.primitives[i]);
    RTCGeometry g = rtcNewGeometry(impl_->device, RTC_GEOMETRY_TYPE_TRIANGLE);
    auto* vb = static_cast<float*>(rtcSetNewGeometryBuffer(g, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3,
                                                           3 * sizeof(float), mesh.vertices_w.size()));
    for (std::size_t k = 0; k < mesh.vertices_w.size(); ++k)
      std::memcpy(vb + 3 * k, mesh.vertices_w[k].data(), 3 * sizeof(float));
    auto* ib = static_cast<unsigned*>(rtcSetNewGeometryBuffer(g, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3,
                                                              3 * sizeof(unsigned), mesh.triangles.size()));
    for (std::size_t k = 0; k < mesh.triangles.size(); ++k)
      for (int c = 0; c < 3; ++c) ib[3 * k + c] = static_cast<unsigned>(mesh.triangles[k][c]);
    rtcCommitGeometry(g);
    rtcAttachGeometryByID(impl_->scene, g, static_cast<unsigned>(i));
    rtcReleaseGeometry(g);
    impl_->triangles += mesh.triangles.size();
  }
  rtcCommitScene(impl_->scene);
  if (const RTCError e = rtcGetDeviceError(impl_->device); e != RTC_ERROR_NONE)
    throw Error("Embree: building the scene BVH failed (error " + std::to_string(static_cast<int>(e)) + ")");
}

Raycaster::~Raycaster() = default;
Raycaster::Raycaster(Raycaster&&) noexcept = default;
Raycaster& Raycaster::operator=(Raycaster&&) noexcept = default;

std::size_t Raycaster::triangle_count() const { return impl_->triangles; }

void Raycaster::intersect(RayPacket& p) const {
  alignas(32) RTCRayHit8 rh;
  for (int i = 0; i < kPacket; ++i) {
    rh.ray.org_x[i] = p.ox[i];
    rh.ray.org_y[i] = p.oy[i];
    rh.ray.org_z[i] = p.oz[i];
    rh.ray.dir_x[i] = p.dx[i];
    rh.ray.dir_y[i] = p.dy[i];
    rh.ray.dir_z[i] = p.dz[i];
    rh.ray.tnear[i] = 0.0f;
    rh.ray.tfar[i] = p.t_max[i];
    rh.ray.time[i] = 0.0f;
    rh.ray.mask[i] = 0xFFFFFFFFu;
    rh.ray.id[i] = 0;
    rh.ray.flags[i] = 0;
    rh.hit.geomID[i] = RTC_INVALID_GEOMETRY_ID;
    rh.hit.instID[0][i] = RTC_INVALID_GEOMETRY_ID;
  }
  RTCIntersectContext ctx;
  rtcInitIntersectContext(&ctx);
  ctx.flags = RTC_INTERSECT_CONTEXT_FLAG_COHERENT;
  rtcIntersect8(p.active, impl_->scene, &ctx, &rh);
  for (int i = 0; i < kPacket; ++i) {
    const bool hit = p.active[i] && rh.hit.geomID[i] != RTC_INVALID_GEOMETRY_ID;
    p.t_hit[i] = hit ? rh.ray.tfar[i] : std::numeric_limits<float>::infinity();
    p.prim[i] = hit ? static_cast<int>(rh.hit.geomID[i]) : -1;
  }
}

}  // namespace s3m::sim
