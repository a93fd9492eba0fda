#include "s3m/sim/texture.hpp"

#include <algorithm>
#include <cmath>

namespace s3m::sim {
namespace {

using Vec3f = Eigen::Vector3f;

inline std::uint32_t hash32(std::int32_t x, std::int32_t y, std::uint32_t seed) {
  std::uint32_t h = seed * 0x9E3779B1u ^ static_cast<std::uint32_t>(x) * 0x85EBCA77u ^
                    static_cast<std::uint32_t>(y) * 0xC2B2AE3Du;
  h ^= h >> 15;
  h *= 0x2C1B3C6Du;
  h ^= h >> 12;
  h *= 0x297A2D39u;
  h ^= h >> 15;
  return h;
}
inline float hash01(std::int32_t x, std::int32_t y, std::uint32_t seed) {
  return static_cast<float>(hash32(x, y, seed) >> 8) * (1.0f / 16777216.0f);
}
inline float fract(float x) { return x - std::floor(x); }
inline float smooth(float t) { return t * t * (3.0f - 2.0f * t); }
inline Vec3f mix(const Vec3f& a, const Vec3f& b, float t) { return a + (b - a) * t; }

inline float vnoise(float x, float y, std::uint32_t seed) {
  const float fx = std::floor(x), fy = std::floor(y);
  const int ix = static_cast<int>(fx), iy = static_cast<int>(fy);
  const float tx = smooth(x - fx), ty = smooth(y - fy);
  const float a = hash01(ix, iy, seed), b = hash01(ix + 1, iy, seed);
  const float c = hash01(ix, iy + 1, seed), d = hash01(ix + 1, iy + 1, seed);
  const float ab = a + (b - a) * tx;
  return ab + ((c + (d - c) * tx) - ab) * ty;
}

float fbm(float x, float y, std::uint32_t seed, int octaves) {
  float sum = 0.0f, amp = 0.5f, norm = 0.0f;
  for (int o = 0; o < octaves; ++o) {
    sum += amp * vnoise(x, y, seed + 101u * o);
    norm += amp;
    x *= 2.03f;
    y *= 2.03f;
    amp *= 0.5f;
  }
  return sum / norm;
}

// A saturated colour from a hash, for books, posters, screen windows.
Vec3f palette(std::uint32_t h) {
  static const Vec3f kColours[] = {{0.75f, 0.12f, 0.10f}, {0.10f, 0.30f, 0.70f}, {0.90f, 0.75f, 0.15f},
                                   {0.12f, 0.55f, 0.25f}, {0.85f, 0.85f, 0.80f}, {0.08f, 0.08f, 0.10f},
                                   {0.60f, 0.30f, 0.60f}, {0.90f, 0.45f, 0.10f}, {0.20f, 0.60f, 0.65f}};
  return kColours[h % (sizeof(kColours) / sizeof(kColours[0]))];
}

// Face coordinates: (s, t) in metres on the face the normal points out of, t "up" where the
// face is vertical; (hs, ht) are the face's half sizes.
struct FaceUv {
  float s, t, hs, ht;
};
FaceUv face_uv(const Vec3f& p, const Vec3f& n, const Vec3f& h) {
  const Vec3f a = n.cwiseAbs();
  if (a.z() >= a.x() && a.z() >= a.y()) return {p.x(), p.y(), h.x(), h.y()};
  if (a.x() >= a.y()) return {n.x() > 0 ? -p.y() : p.y(), p.z(), h.y(), h.z()};
  return {n.y() > 0 ? p.x() : -p.x(), p.z(), h.x(), h.z()};
}

Vec3f paint(const Material& m, const FaceUv& f) {
  const float blot = fbm(f.s / m.scale_m, f.t / m.scale_m, m.seed, 2);
  Vec3f c = m.base * (0.88f + 0.24f * blot);
  if (blot > 0.66f) c = mix(c, m.accent, 0.35f);  // sharp-edged stains give corners
  const float speck = hash01(static_cast<int>(f.s * 200.0f), static_cast<int>(f.t * 200.0f), m.seed ^ 7u);
  return c * (0.94f + 0.12f * speck);
}

Vec3f wood(const Material& m, const FaceUv& f) {
  const float warp = fbm(f.s * 2.0f, f.t * 8.0f, m.seed, 2);
  const float ring = fract((f.t + 0.15f * warp) / m.scale_m * 6.0f + 0.3f * std::sin(f.s * 3.0f));
  const float grain = smooth(std::clamp(std::abs(ring - 0.5f) * 2.0f, 0.0f, 1.0f));
  const float plank = fract(f.t / (m.scale_m * 2.0f));
  Vec3f c = mix(m.accent, m.base, grain);
  if (plank < 0.02f) c *= 0.45f;  // plank seams
  const float knot = vnoise(f.s * 6.0f, f.t * 6.0f, m.seed ^ 0xABCu);
  return c * (0.85f + 0.3f * knot);
}

Vec3f tiles(const Material& m, const FaceUv& f) {
  const float u = f.s / m.scale_m, v = f.t / m.scale_m;
  const int iu = static_cast<int>(std::floor(u)), iv = static_cast<int>(std::floor(v));
  const float fu = u - iu, fv = v - iv;
  if (fu < 0.04f || fv < 0.04f) return m.accent;  // grout
  const float jitter = hash01(iu, iv, m.seed);
  Vec3f c = m.base * (0.8f + 0.35f * jitter);
  if (hash32(iu, iv, m.seed ^ 3u) % 7 == 0) c = mix(c, m.accent, 0.5f);
  return c * (0.9f + 0.2f * fbm(u * 4.0f, v * 4.0f, m.seed ^ 5u, 2));
}

Vec3f carpet(const Material& m, const FaceUv& f) {
  const float fibre = hash01(static_cast<int>(f.s * 300.0f), static_cast<int>(f.t * 300.0f), m.seed);
  const float patch = fbm(f.s / m.scale_m, f.t / m.scale_m, m.seed ^ 9u, 2);
  Vec3f c = mix(m.base, m.accent, smooth(std::clamp((patch - 0.35f) * 3.0f, 0.0f, 1.0f)));
  return c * (0.75f + 0.4f * fibre);
}

Vec3f fabric(const Material& m, const FaceUv& f) {
  const float weave = 0.5f + 0.25f * (std::sin(f.s * 600.0f) + std::sin(f.t * 600.0f));
  const float check = (static_cast<int>(std::floor(f.s / m.scale_m)) + static_cast<int>(std::floor(f.t / m.scale_m))) & 1;
  Vec3f c = mix(m.base, m.accent, 0.25f * check);
  return c * (0.8f + 0.2f * weave) * (0.85f + 0.3f * fbm(f.s * 5.0f, f.t * 5.0f, m.seed, 2));
}

Vec3f books(const Material& m, const FaceUv& f) {
  // Spines along s, each 2-6 cm wide; variable heights leave dark gaps above.
  const float w = 0.04f;
  const int i = static_cast<int>(std::floor(f.s / w));
  const std::uint32_t h = hash32(i, 0, m.seed);
  const float height = 0.45f + 0.5f * ((h >> 8) & 255) / 255.0f;  // fraction of shelf compartment
  const float level = fract((f.t + f.ht) / m.scale_m);
  if (level > height || fract(f.s / w) < 0.06f) return m.accent * 0.3f;
  Vec3f c = palette(h);
  if (std::abs(level - 0.2f) < 0.02f || std::abs(level - height + 0.08f) < 0.015f) c = Vec3f(0.9f, 0.85f, 0.6f);
  return c;
}

Vec3f screen(const Material& m, const FaceUv& f) {
  const float bs = f.hs - 0.025f, bt = f.ht - 0.025f;  // 2.5 cm bezel
  if (std::abs(f.s) > bs || std::abs(f.t) > bt) return Vec3f(0.03f, 0.03f, 0.035f);
  const float u = (f.s + bs) / (2 * bs), v = (f.t + bt) / (2 * bt);
  Vec3f c = m.base;  // desktop colour
  for (int k = 0; k < 3; ++k) {  // three application windows
    const std::uint32_t h = hash32(k, 1, m.seed);
    const float x0 = 0.05f + 0.45f * ((h & 255) / 255.0f), y0 = 0.1f + 0.4f * (((h >> 8) & 255) / 255.0f);
    if (u > x0 && u < x0 + 0.45f && v > y0 && v < y0 + 0.4f) {
      c = (v > y0 + 0.34f) ? palette(h >> 16) : Vec3f(0.92f, 0.92f, 0.9f);
      const float line = fract((v - y0) * 25.0f);
      if (v < y0 + 0.32f && line < 0.35f && hash01(static_cast<int>(u * 40), static_cast<int>(v * 25), h) > 0.3f)
        c = Vec3f(0.15f, 0.15f, 0.2f);  // text lines
    }
  }
  return c;
}

Vec3f poster(const Material& m, const FaceUv& f) {
  const float u = (f.s + f.hs) / m.scale_m, v = (f.t + f.ht) / m.scale_m;
  if (std::abs(f.s) > f.hs - 0.02f || std::abs(f.t) > f.ht - 0.02f) return m.accent;  // frame
  const int iu = static_cast<int>(std::floor(u)), iv = static_cast<int>(std::floor(v));
  const std::uint32_t h = hash32(iu, iv, m.seed);
  const float fu = u - iu - 0.5f, fv = v - iv - 0.5f;
  Vec3f bg = m.base;
  switch (h % 4) {
    case 0: return (fu * fu + fv * fv < 0.12f) ? palette(h >> 4) : bg;
    case 1: return (std::abs(fu) < 0.35f && std::abs(fv) < 0.2f) ? palette(h >> 6) : bg;
    case 2: return (fract(v * 4.0f) < 0.3f && std::abs(fu) < 0.4f) ? Vec3f(0.1f, 0.1f, 0.12f) : bg;
    default: return (fu + fv > 0.0f) ? palette(h >> 9) : palette(h >> 13);
  }
}

Vec3f sky(const Material& m, const FaceUv& f) {
  const float v = (f.t + f.ht) / (2 * f.ht);
  if (std::abs(f.s) > f.hs - 0.05f || std::abs(f.t) > f.ht - 0.05f ||
      std::abs(f.s) < 0.02f)  // window frame and mullion
    return m.accent;
  // Skyline of buildings: per-column heights.
  const int col = static_cast<int>(std::floor((f.s + f.hs) / 0.12f));
  const std::uint32_t h = hash32(col, 2, m.seed);
  const float roof = 0.15f + 0.35f * ((h & 255) / 255.0f);
  if (v < roof) {
    const bool lit = hash01(static_cast<int>(f.s * 30.0f), static_cast<int>(f.t * 22.0f), m.seed) > 0.6f;
    return lit ? Vec3f(0.9f, 0.85f, 0.6f) : Vec3f(0.25f, 0.25f, 0.3f) * (0.8f + 0.4f * ((h >> 8 & 255) / 255.0f));
  }
  const float cloud = fbm(f.s * 3.0f, f.t * 6.0f, m.seed ^ 77u, 3);
  return mix(m.base, Vec3f(0.95f, 0.95f, 0.97f), smooth(std::clamp((cloud - 0.45f) * 4.0f, 0.0f, 1.0f)));
}

Vec3f foliage(const Material& m, const Vec3f& p) {
  const float x = p.x() / m.scale_m, y = p.y() / m.scale_m, z = p.z() / m.scale_m;
  const float a = vnoise(x + 0.5f * z, y, m.seed), b = vnoise(y + 0.3f * z, z, m.seed ^ 1u);
  const float leaf = hash01(static_cast<int>(std::floor(x * 3 + z)), static_cast<int>(std::floor(y * 3 - z)), m.seed);
  Vec3f c = mix(m.base, m.accent, a);
  if (leaf > 0.7f) c *= 1.4f;
  return c * (0.6f + 0.6f * b);
}

Vec3f metal(const Material& m, const FaceUv& f) {
  const float streak = hash01(static_cast<int>(f.s * 400.0f), 0, m.seed);
  return m.base * (0.85f + 0.2f * streak);
}

Vec3f panel(const Material& m, const FaceUv& f) {
  const float in = 0.07f;
  const float ds = f.hs - std::abs(f.s), dt = f.ht - std::abs(f.t);
  Vec3f c = wood(m, f);
  if (std::abs(ds - in) < 0.012f || std::abs(dt - in) < 0.012f) c *= 0.4f;  // groove of the inset
  if (std::abs(f.t) < 0.25f * f.ht && std::abs(f.s - 0.75f * f.hs) < 0.02f) c = Vec3f(0.8f, 0.78f, 0.7f);  // handle
  return c;
}

}  // namespace

float value_noise(float x, float y, std::uint32_t seed) { return vnoise(x, y, seed); }

Eigen::Vector3f albedo(const Material& m, Shape shape, const Eigen::Vector3f& half_extents_m,
                       const Eigen::Vector3f& p_p, const Eigen::Vector3f& n_p) {
  if (m.pattern == Pattern::kFoliage) return foliage(m, p_p);
  FaceUv f = face_uv(p_p, n_p, half_extents_m);
  if (shape != Shape::kBox) {  // wrap curved surfaces by angle so patterns do not smear
    const float r = half_extents_m.x();
    f = {std::atan2(p_p.y(), p_p.x()) * r, p_p.z(), 3.1416f * r, half_extents_m.z()};
  }
  Vec3f c;
  switch (m.pattern) {
    case Pattern::kPaint: c = paint(m, f); break;
    case Pattern::kWood: c = wood(m, f); break;
    case Pattern::kTiles: c = tiles(m, f); break;
    case Pattern::kCarpet: c = carpet(m, f); break;
    case Pattern::kFabric: c = fabric(m, f); break;
    case Pattern::kBooks: c = books(m, f); break;
    case Pattern::kScreen: c = screen(m, f); break;
    case Pattern::kPoster: c = poster(m, f); break;
    case Pattern::kSky: c = sky(m, f); break;
    case Pattern::kMetal: c = metal(m, f); break;
    case Pattern::kPanel: c = panel(m, f); break;
    default: c = m.base; break;
  }
  return c.cwiseMax(0.0f).cwiseMin(1.0f);
}

}  // namespace s3m::sim
