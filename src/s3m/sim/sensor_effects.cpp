#include "s3m/sim/sensor_effects.hpp"

#include <cmath>

#include <opencv2/imgproc.hpp>

namespace s3m::sim {

void fatten_edges(cv::Mat& depth_m, int px, double jump_rel) {
  if (px <= 0) return;
  // Missing depth must not win the minimum: it is no surface.
  cv::Mat valid_or_far = depth_m.clone();
  valid_or_far.setTo(std::numeric_limits<float>::max(), depth_m <= 0.0f);
  cv::Mat nearest;
  cv::erode(valid_or_far, nearest,
            cv::getStructuringElement(cv::MORPH_RECT, cv::Size(2 * px + 1, 2 * px + 1)), cv::Point(-1, -1), 1,
            cv::BORDER_REPLICATE);
  const float keep = static_cast<float>(1.0 - jump_rel);
  for (int r = 0; r < depth_m.rows; ++r) {
    float* z = depth_m.ptr<float>(r);
    const float* n = nearest.ptr<float>(r);
    for (int u = 0; u < depth_m.cols; ++u)
      if (z[u] > 0.0f && n[u] < keep * z[u]) z[u] = n[u];
  }
}

void quantise_disparity(cv::Mat& depth_m, double fx_b_px_m, double step_px) {
  if (step_px <= 0) return;
  for (int r = 0; r < depth_m.rows; ++r) {
    float* z = depth_m.ptr<float>(r);
    for (int u = 0; u < depth_m.cols; ++u) {
      if (z[u] <= 0.0f) continue;
      const double steps = std::round(fx_b_px_m / z[u] / step_px);
      z[u] = steps > 0 ? static_cast<float>(fx_b_px_m / (steps * step_px)) : 0.0f;
    }
  }
}

SE3 misregistered_depth_camera(double error_px, double fx) {
  // A camera turned by +a about y sees a point on the colour axis at u = cx - fx tan(a).
  SE3 T_c_d = SE3::Identity();
  T_c_d.linear() = Eigen::AngleAxisd(-std::atan(error_px / fx), Vec3::UnitY()).toRotationMatrix();
  return T_c_d;
}

std::vector<SE3> rolling_shutter_poses(const std::function<SE3(double)>& T_w_c_at, double t_first_s,
                                       double readout_s, int rows) {
  std::vector<SE3> out;
  out.reserve(rows);
  for (int r = 0; r < rows; ++r) {  // the fraction first: the last row is exactly readout_s late
    const double fraction = rows > 1 ? static_cast<double>(r) / (rows - 1) : 0.0;
    out.push_back(T_w_c_at(t_first_s + readout_s * fraction));
  }
  return out;
}

}  // namespace s3m::sim
