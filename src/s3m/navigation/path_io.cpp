#include "s3m/navigation/path_io.hpp"

#include <cmath>
#include <cstdio>

#include <Eigen/Geometry>

#include "s3m/core/atomic_file.hpp"
#include "s3m/core/error.hpp"

namespace s3m::navigation {

void write_path_tum(const std::string& path, const std::vector<Eigen::Vector3d>& waypoints_w,
                    double speed_mps) {
  require(speed_mps > 0.0, "write_path_tum: speed_mps must be > 0");
  std::string text = "# planned path: timestamp tx ty tz qx qy qz qw (t = arc length / " +
                     std::to_string(speed_mps) + " m/s)\n";
  double t = 0.0, yaw = 0.0;
  for (std::size_t i = 0; i < waypoints_w.size(); ++i) {
    const Eigen::Vector3d& p = waypoints_w[i];
    if (i > 0) t += (p - waypoints_w[i - 1]).norm() / speed_mps;
    if (i + 1 < waypoints_w.size()) {
      const Eigen::Vector3d d = waypoints_w[i + 1] - p;
      if (d.head<2>().norm() > 1e-9) yaw = std::atan2(d.y(), d.x());
    }
    const Eigen::Quaterniond q(Eigen::AngleAxisd(yaw, Eigen::Vector3d::UnitZ()));
    char line[200];
    std::snprintf(line, sizeof line, "%.6f %.6f %.6f %.6f %.9f %.9f %.9f %.9f\n", t, p.x(), p.y(), p.z(),
                  q.x(), q.y(), q.z(), q.w());
    text += line;
  }
  write_text_atomic(path, text);
}

}  // namespace s3m::navigation
