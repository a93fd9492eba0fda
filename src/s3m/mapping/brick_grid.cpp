#include "s3m/mapping/brick_grid.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

#include <tbb/parallel_for.h>
#include <tbb/task_arena.h>

namespace s3m::mapping {

bool KeyCoder::key_checked(const octomap::point3d& p, octomap::OcTreeKey& key) const {
  for (int a = 0; a < 3; ++a) {
    const int scaled = int(std::floor(inv_res * double(p(a)))) + kMaxVal;
    if (scaled < 0 || scaled >= 2 * kMaxVal) return false;
    key[a] = std::uint16_t(scaled);
  }
  return true;
}

void BrickGrid::reset(const octomap::OcTreeKey& lo, const octomap::OcTreeKey& hi) {
  for (int a = 0; a < 3; ++a) lo_[a] = lo[a] >> 3;
  nx_ = std::size_t((hi[0] >> 3) - lo_[0] + 1);
  ny_ = std::size_t((hi[1] >> 3) - lo_[1] + 1);
  nz_ = std::size_t((hi[2] >> 3) - lo_[2] + 1);
  const std::size_t n[3] = {nx_, ny_, nz_}, stride[3] = {1, nx_, nx_ * ny_};
  for (int a = 0; a < 3; ++a) {
    base_[a] = lo_[a] * 8;
    extent_[a] = unsigned(n[a] * 8);
    brick_off_[a].resize(extent_[a]);
    bit_off_[a].resize(extent_[a]);
    for (unsigned i = 0; i < extent_[a]; ++i) {
      brick_off_[a][i] = (i >> 3) * stride[a];
      // In-brick bit b = (c14 << 6) | (c15 << 3) | c16, child index c = x | y << 1 | z << 2.
      bit_off_[a][i] = std::uint16_t((((i >> 2) & 1u) << (6 + a)) | (((i >> 1) & 1u) << (3 + a)) | ((i & 1u) << a));
    }
  }
  const std::size_t words = nx_ * ny_ * nz_ * 8;
  free_.assign(words, 0);
  occ_.assign(words, 0);
}

int BrickGrid::occupied_neighbors(const octomap::OcTreeKey& k, int enough) const {
  int count = 0;
  for (int dz = -1; dz <= 1; ++dz)
    for (int dy = -1; dy <= 1; ++dy)
      for (int dx = -1; dx <= 1; ++dx) {
        if ((dx | dy | dz) == 0) continue;
        const octomap::OcTreeKey n(std::uint16_t(k[0] + dx), std::uint16_t(k[1] + dy), std::uint16_t(k[2] + dz));
        if (occupied(n) && ++count >= enough) return count;
      }
  return count;
}

namespace {
// OcTreeBaseImpl::computeRayKeys (Amanatides & Woo DDA) with the same float/double mix, so the
// free voxels are exactly OctoMap's; visit() gets every key of the ray except the end voxel.
template <typename Visit>
void walk_ray(const KeyCoder& coder, const octomap::point3d& origin, const octomap::point3d& end, Visit&& visit) {
  octomap::OcTreeKey key_origin, key_end;
  if (!coder.key_checked(origin, key_origin) || !coder.key_checked(end, key_end)) return;
  if (key_origin == key_end) return;
  visit(int(key_origin[0]), int(key_origin[1]), int(key_origin[2]));
  octomap::point3d direction = end - origin;
  const float length = float(direction.norm());
  direction /= length;
  int step[3];
  double t_max[3], t_delta[3];
  octomap::OcTreeKey current = key_origin;
  for (int i = 0; i < 3; ++i) {
    step[i] = direction(i) > 0.0 ? 1 : (direction(i) < 0.0 ? -1 : 0);
    if (step[i] != 0) {
      double border = coder.center(current[i]);
      border += float(step[i] * coder.res * 0.5);
      t_max[i] = (border - origin(i)) / direction(i);
      t_delta[i] = coder.res / std::fabs(direction(i));
    } else {
      t_max[i] = t_delta[i] = std::numeric_limits<double>::max();
    }
  }
  // Scalar state instead of indexed arrays: this loop runs millions of times per frame.
  int cx = current[0], cy = current[1], cz = current[2];
  const int ex = key_end[0], ey = key_end[1], ez = key_end[2];
  double tx = t_max[0], ty = t_max[1], tz = t_max[2];
  while (true) {
    if (tx < ty) {
      if (tx < tz) cx += step[0], tx += t_delta[0];
      else cz += step[2], tz += t_delta[2];
    } else {
      if (ty < tz) cy += step[1], ty += t_delta[1];
      else cz += step[2], tz += t_delta[2];
    }
    if (cx == ex && cy == ey && cz == ez) return;
    if (std::min(std::min(tx, ty), tz) > length) return;
    visit(cx, cy, cz);
  }
}
}  // namespace

void BrickGrid::cast_rays(const KeyCoder& coder, const octomap::point3d& origin,
                          const std::vector<octomap::point3d>& ends) {
  // Each task marks its own bitmap; OR-ing them is order independent, hence deterministic.
  const std::size_t parts = std::clamp<std::size_t>(std::size_t(tbb::this_task_arena::max_concurrency()), 1,
                                                    std::max<std::size_t>(1, ends.size() / 256));
  free_parts_.resize(parts);
  tbb::parallel_for(std::size_t(0), parts, [&](std::size_t part) {
    std::vector<std::uint64_t>& bits = part == 0 ? free_ : free_parts_[part];
    if (part > 0) bits.assign(free_.size(), 0);
    const std::size_t begin = ends.size() * part / parts, end = ends.size() * (part + 1) / parts;
    for (std::size_t i = begin; i < end; ++i)
      walk_ray(coder, origin, ends[i], [&](int x, int y, int z) { mark(bits, x, y, z); });
  });
  if (parts == 1) return;
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, free_.size(), 1 << 14), [&](const auto& r) {
    for (std::size_t p = 1; p < parts; ++p)
      for (std::size_t w = r.begin(); w < r.end(); ++w) free_[w] |= free_parts_[p][w];
  });
}

void BrickGrid::build_bricks(FrameUpdate& out) const {
  out.bricks.clear();
  for (std::size_t bz = 0; bz < nz_; ++bz)
    for (std::size_t by = 0; by < ny_; ++by)
      for (std::size_t bx = 0; bx < nx_; ++bx) {
        const std::size_t base = ((bz * ny_ + by) * nx_ + bx) * 8;
        std::uint64_t any = 0;
        for (int w = 0; w < 8; ++w) any |= free_[base + w] | occ_[base + w];
        if (!any) continue;
        BrickUpdate& b = out.bricks.emplace_back();
        b.morton = brick_morton(unsigned(lo_[0] + int(bx)), unsigned(lo_[1] + int(by)), unsigned(lo_[2] + int(bz)));
        for (int w = 0; w < 8; ++w) {
          b.occupied[w] = occ_[base + w];
          b.free[w] = free_[base + w] & ~occ_[base + w];
        }
      }
  std::sort(out.bricks.begin(), out.bricks.end(),
            [](const BrickUpdate& a, const BrickUpdate& b) { return a.morton < b.morton; });
}

}  // namespace s3m::mapping
