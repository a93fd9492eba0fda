#include "s3m/rosbag2/camera_info.hpp"

#include <algorithm>
#include <cmath>

#include <Eigen/Dense>

#include "s3m/core/error.hpp"

namespace s3m::rosbag2 {
namespace {

// Fits k1 k2 p1 p2 k3 to the rational model over a grid of the image: the distortion offset is
// linear in the Brown-Conrady coefficients, so this is one linear least-squares problem.
std::array<double, 5> brown_conrady_from_rational(const std::vector<double>& c, const CameraInfo& info) {
  const int n = 21;
  Eigen::MatrixXd A(2 * n * n, 5);
  Eigen::VectorXd b(2 * n * n);
  int row = 0;
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < n; ++j) {
      // Undistorted normalised points spanning the image (the distortion is mild enough that the
      // undistorted grid over the image's extent covers what the pixels see).
      const double x = (i * (info.width - 1.0) / (n - 1) - info.k[2]) / info.k[0];
      const double y = (j * (info.height - 1.0) / (n - 1) - info.k[5]) / info.k[4];
      const double r2 = x * x + y * y, r4 = r2 * r2, r6 = r4 * r2;
      const double radial = (1 + c[0] * r2 + c[1] * r4 + c[4] * r6) / (1 + c[5] * r2 + c[6] * r4 + c[7] * r6);
      const double xd = x * radial + 2 * c[2] * x * y + c[3] * (r2 + 2 * x * x);
      const double yd = y * radial + c[2] * (r2 + 2 * y * y) + 2 * c[3] * x * y;
      A.row(row) << x * r2, x * r4, 2 * x * y, r2 + 2 * x * x, x * r6;
      b(row++) = xd - x;
      A.row(row) << y * r2, y * r4, r2 + 2 * y * y, 2 * x * y, y * r6;
      b(row++) = yd - y;
    }
  const Eigen::VectorXd k = A.colPivHouseholderQr().solve(b);
  return {k(0), k(1), k(2), k(3), k(4)};
}

}  // namespace

PinholeCamera camera_from_info(const CameraInfo& info, double default_bf, const std::string& where) {
  PinholeCamera c;
  c.fx = info.k[0], c.fy = info.k[4], c.cx = info.k[2], c.cy = info.k[5];
  c.width = static_cast<int>(info.width), c.height = static_cast<int>(info.height);
  c.dist = {0, 0, 0, 0, 0};
  std::vector<double> d = info.d;
  d.resize(std::max<std::size_t>(d.size(), 8), 0.0);
  const bool none = std::all_of(d.begin(), d.end(), [](double x) { return x == 0.0; });
  const std::string& model = info.distortion_model;
  if (none) {
    // no distortion, whatever the model is called
  } else if (model == "rational_polynomial" && (d[5] != 0 || d[6] != 0 || d[7] != 0)) {
    c.dist = brown_conrady_from_rational(d, info);
  } else if (model == "plumb_bob" || model == "rational_polynomial") {
    for (std::size_t i = 0; i < 5; ++i) c.dist[i] = d[i];
  } else {
    throw Error(where + ": distortion model '" + model + "' (expected plumb_bob or rational_polynomial)");
  }
  c.bf = info.p[3] < 0 ? -info.p[3] : default_bf;
  c.depth_factor = 1000.0;  // unused: depth arrives converted to metres
  try {
    c.validate();
  } catch (const Error& e) {
    throw Error(where + ": " + e.what());
  }
  return c;
}

bool info_matches(const CameraInfo& info, const PinholeCamera& camera) {
  return static_cast<int>(info.width) == camera.width &&
         !(std::abs(info.k[0] - camera.fx) > 0.01 * camera.fx);
}

}  // namespace s3m::rosbag2
