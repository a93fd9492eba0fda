#pragma once
// Counter-based random numbers for the simulator. Every random draw is a pure function of
// (seed, stream, index), so results do not depend on thread scheduling or draw order, and the
// same arguments give byte-identical sequences on every platform (std:: distributions are not
// specified bit-exactly across standard libraries, hence this tiny hand-rolled generator).
#include <cmath>
#include <cstdint>

namespace s3m::sim {

// SplitMix64 finaliser: a well-mixed 64-bit hash.
inline std::uint64_t mix64(std::uint64_t x) {
  x += 0x9E3779B97F4A7C15ull;
  x = (x ^ (x >> 30)) * 0xBF58476D1CE4E5B9ull;
  x = (x ^ (x >> 27)) * 0x94D049BB133111EBull;
  return x ^ (x >> 31);
}

inline std::uint64_t hash3(std::uint64_t a, std::uint64_t b, std::uint64_t c) {
  return mix64(mix64(mix64(a) ^ b) ^ c);
}

// Uniform in [0, 1) from the top 53 bits of a hash.
inline double u01(std::uint64_t h) { return static_cast<double>(h >> 11) * (1.0 / 9007199254740992.0); }

// Sequential generator for scene layout (single-threaded code where draw order is fixed).
class Rng {
 public:
  explicit Rng(std::uint64_t seed) : state_(mix64(seed ^ 0x5EEDull)) {}
  std::uint64_t next() { return mix64(state_++); }
  double uniform() { return u01(next()); }
  double uniform(double lo, double hi) { return lo + (hi - lo) * uniform(); }
  int integer(int lo, int hi_inclusive) {
    return lo + static_cast<int>(uniform() * (hi_inclusive - lo + 1));
  }
  bool chance(double p) { return uniform() < p; }

 private:
  std::uint64_t state_;
};

// Standard normal from two independent hashes (Box-Muller).
inline double gaussian(std::uint64_t h1, std::uint64_t h2) {
  const double u1 = u01(h1) + 1e-300;  // avoid log(0)
  const double u2 = u01(h2);
  return std::sqrt(-2.0 * std::log(u1)) * std::cos(6.283185307179586 * u2);
}

// Single-precision variant for per-pixel sensor noise (float log/cos are ~2x cheaper).
inline float gaussian_f(std::uint64_t h) {
  const float u1 = static_cast<float>((h >> 40) + 1) * (1.0f / 16777217.0f);  // (0, 1]
  const float u2 = static_cast<float>(h & 0xFFFFFF) * (1.0f / 16777216.0f);
  return std::sqrt(-2.0f * std::log(u1)) * std::cos(6.2831853f * u2);
}

}  // namespace s3m::sim
