#include "s3m/features/depth_noise_estimator.hpp"

#include <algorithm>
#include <cmath>

#include <fmt/format.h>

#include "s3m/core/error.hpp"

namespace s3m::features {
namespace {

double median(std::vector<float> v) {
  const auto mid = v.begin() + std::ptrdiff_t(v.size() / 2);
  std::nth_element(v.begin(), mid, v.end());
  return *mid;
}

void push_ring(std::vector<float>& ring, std::size_t& next, std::size_t cap, float value) {
  if (ring.size() < cap) {
    ring.push_back(value);
    return;
  }
  ring[next] = value;
  next = (next + 1) % cap;
}

// Least squares of sigma = s0 + k z^2 over the bins (each weighted by its count), with s0, k >= 0:
// when the free solution has a negative coefficient, the best fit with that one at 0.
void fit(DepthNoiseEstimate& e) {
  double sw = 0, sx = 0, sxx = 0, sy = 0, sxy = 0;
  for (const auto& b : e.bins) {
    const double w = b.n, x = b.z_m * b.z_m, y = b.sigma_m;
    sw += w, sx += w * x, sxx += w * x * x, sy += w * y, sxy += w * x * y;
  }
  const double det = sw * sxx - sx * sx;
  double s0 = det > 0 ? (sxx * sy - sx * sxy) / det : -1, k = det > 0 ? (sw * sxy - sx * sy) / det : -1;
  if (s0 < 0 || k < 0) {
    const double only_k = sxx > 0 ? sxy / sxx : 0;  // s0 = 0
    const double only_s0 = sy / sw;                 // k = 0
    auto cost = [&](double a, double b) {
      double c = 0;
      for (const auto& bin : e.bins) c += bin.n * std::pow(a + b * bin.z_m * bin.z_m - bin.sigma_m, 2);
      return c;
    };
    if (cost(0, only_k) < cost(only_s0, 0))
      s0 = 0, k = only_k;
    else
      s0 = only_s0, k = 0;
  }
  e.sigma0_m = s0;
  e.k_per_m = k;
  e.fitted = true;
}

}  // namespace

std::string describe(const DepthNoiseEstimate& e) {
  std::string s = fmt::format("depth residuals of {} tracked map points", e.samples);
  if (!e.bins.empty()) {
    s += ": sigma";
    for (const auto& b : e.bins) s += fmt::format(" {:.1f} mm at {:.2f} m,", 1e3 * b.sigma_m, b.z_m);
    s.pop_back();
  }
  if (e.fitted) s += fmt::format("; fit {:.2f} mm + {:.2f} mm/m^2 z^2", 1e3 * e.sigma0_m, 1e3 * e.k_per_m);
  s += e.offset_frames == 0 ? "; colour and depth taken together"
                            : fmt::format(
                                  "; colour-depth offset median {:.1f} ms (largest {:.1f} ms) in {} frames, "
                                  "compensated by the motion model",
                                  1e3 * e.offset_median_s, 1e3 * e.offset_max_abs_s, e.offset_frames);
  return s;
}

DepthNoiseEstimator::DepthNoiseEstimator(double bin_m, double max_depth_m, std::size_t cap_per_bin)
    : bin_m_(bin_m), cap_(cap_per_bin) {
  require(bin_m > 0 && max_depth_m > bin_m && cap_per_bin > 0,
          "DepthNoiseEstimator: need bin_m > 0, max_depth_m > bin_m and cap_per_bin > 0");
  bins_.resize(static_cast<std::size_t>(std::ceil(max_depth_m / bin_m)));
}

void DepthNoiseEstimator::add(double z_measured_m, double z_predicted_m) {
  if (!(z_measured_m > 0) || !(z_predicted_m > 0) || !std::isfinite(z_predicted_m)) return;
  // Binned by the map point's depth: binned by the measurement, a bin would hold the residuals that
  // pushed a depth into it and not those that pushed it out.
  const auto b = static_cast<std::size_t>(z_predicted_m / bin_m_);
  if (b >= bins_.size()) return;
  push_ring(bins_[b].r, bins_[b].next, cap_, static_cast<float>(z_measured_m - z_predicted_m));
  ++samples_;
}

void DepthNoiseEstimator::add_offset(double depth_dt_s) {
  if (depth_dt_s == 0 || !std::isfinite(depth_dt_s)) return;
  push_ring(offsets_, next_offset_, cap_, static_cast<float>(depth_dt_s));
  ++offset_frames_;
}

DepthNoiseEstimate DepthNoiseEstimator::estimate(int min_per_bin) const {
  DepthNoiseEstimate e;
  e.samples = samples_;
  for (std::size_t i = 0; i < bins_.size(); ++i) {
    const auto& r = bins_[i].r;
    if (static_cast<int>(r.size()) < std::max(min_per_bin, 1)) continue;
    const double m = median(r);
    std::vector<float> dev(r.size());
    for (std::size_t j = 0; j < r.size(); ++j) dev[j] = static_cast<float>(std::abs(r[j] - m));
    e.bins.push_back({(double(i) + 0.5) * bin_m_, static_cast<int>(r.size()), 1.4826 * median(dev)});
  }
  if (e.bins.size() >= 2) fit(e);
  e.offset_frames = offset_frames_;
  if (!offsets_.empty()) {
    e.offset_median_s = median(offsets_);
    for (float o : offsets_) e.offset_max_abs_s = std::max(e.offset_max_abs_s, double(std::abs(o)));
  }
  return e;
}

}  // namespace s3m::features
