// The room renderer of slam_synthetic_room.hpp. Rendering is most of a room test's run time (55 %
// under ASan at -O1, 45 % in Release), so the sanitizer build compiles this file optimised and
// without instrumentation (tests/CMakeLists.txt): it makes test input, it is not under test.
#include "slam_synthetic_room.hpp"

#include <cmath>
#include <cstdint>
#include <random>

#include <opencv2/imgproc.hpp>

namespace s3m::test {
namespace {

double cell_value(int a, int b, int face, int scale) {
  std::uint64_t h = 1469598103934665603ull;
  for (std::int64_t v : {std::int64_t(a), std::int64_t(b), std::int64_t(face), std::int64_t(scale)}) {
    h ^= static_cast<std::uint64_t>(v) + 0x9e3779b97f4a7c15ull;
    h *= 1099511628211ull;
    h ^= h >> 29;
  }
  return static_cast<double>(h % 1000) / 1000.0;
}

// Grey level in [0, 255] at wall coordinates (a, b) [m] on a face. Neighbouring pixels mostly fall
// in the same texture cells, so each scale remembers its last cell's value (the same grey levels,
// ~10 % less rendering time).
class RoomTexture {
 public:
  double at(double a, double b, int face) {
    double v = 0;
    for (int s = 0; s < 3; ++s) {
      const int ia = static_cast<int>(std::floor(a / kSizes[s])), ib = static_cast<int>(std::floor(b / kSizes[s]));
      Cell& c = last_[s];
      if (ia != c.a || ib != c.b || face != c.face) c = {ia, ib, face, cell_value(ia, ib, face, s)};
      v += kWeights[s] * c.value;
    }
    return 30.0 + 200.0 * v;
  }

 private:
  static constexpr double kSizes[3] = {0.40, 0.15, 0.06};
  static constexpr double kWeights[3] = {0.5, 0.3, 0.2};
  struct Cell {
    int a = 0, b = 0, face = -1;
    double value = 0;
  };
  Cell last_[3];
};

}  // namespace

RgbdFrame render_room(const Room& room, const PinholeCamera& cam, const SE3& T_w_c, int index, double t_s,
                      double depth_noise_m, unsigned seed) {
  RgbdFrame f;
  f.index = index;
  f.t_s = t_s;
  cv::Mat gray(cam.height, cam.width, CV_8UC1);
  f.depth_m.create(cam.height, cam.width, CV_32FC1);
  const Mat3 R = T_w_c.linear();
  const Vec3 o = T_w_c.translation();
  std::mt19937 rng(seed + 7919u * static_cast<unsigned>(index));
  std::normal_distribution<double> noise(0.0, 1.0);
  RoomTexture texture;
  for (int v = 0; v < cam.height; ++v)
    for (int u = 0; u < cam.width; ++u) {
      const Vec3 d_c((u - cam.cx) / cam.fx, (v - cam.cy) / cam.fy, 1.0);
      const Vec3 d = R * d_c;
      double t_best = 1e9;
      int axis = 0;
      for (int k = 0; k < 3; ++k) {
        if (std::abs(d[k]) < 1e-12) continue;
        const double t = ((d[k] > 0 ? room.hi[k] : room.lo[k]) - o[k]) / d[k];
        if (t > 0 && t < t_best) t_best = t, axis = k;
      }
      const Vec3 p = o + t_best * d;
      const int face = axis * 2 + (d[axis] > 0 ? 1 : 0);
      const double a = p[(axis + 1) % 3], b = p[(axis + 2) % 3];
      gray.at<std::uint8_t>(v, u) = cv::saturate_cast<std::uint8_t>(texture.at(a, b, face));
      f.depth_m.at<float>(v, u) = static_cast<float>(t_best * (1.0 + depth_noise_m * noise(rng)));  // z = t for d_c.z = 1
    }
  cv::GaussianBlur(gray, gray, cv::Size(3, 3), 0.6);
  cv::cvtColor(gray, f.rgb, cv::COLOR_GRAY2BGR);
  return f;
}

}  // namespace s3m::test
