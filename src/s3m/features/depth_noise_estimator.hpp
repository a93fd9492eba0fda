#pragma once
// What tracking learns about the depth sensor from its own inliers, to show the user (metrics.json,
// run log) next to the configured model (DepthNoiseConfig). Per depth bin (of the map point's
// depth): the robust sigma
// (1.4826 MAD) of z_measured - z_predicted over tracked map points, and a least-squares fit
// sigma(z) = sigma0 + k z^2 over the bins. The residual holds the map point's own error as well as
// the sensor's (about sqrt(1 + 1/n) times the sensor's sigma for a point fused from n equally good
// depths), so the curve is an upper bound of the sensor's noise, tight for well-observed points.
// Also the colour-depth time offsets the frames came with (RgbdFrame::depth_dt_s).
#include <cstddef>
#include <string>
#include <vector>

namespace s3m::features {

struct DepthNoiseBin {
  double z_m = 0;      // bin centre [m]
  int n = 0;           // residuals in the bin (at most the estimator's cap)
  double sigma_m = 0;  // 1.4826 * median |residual - median| [m]
};

struct DepthNoiseEstimate {
  long samples = 0;                  // residuals seen in all
  std::vector<DepthNoiseBin> bins;   // bins with at least min_per_bin residuals, nearest first
  bool fitted = false;               // at least two bins
  double sigma0_m = 0, k_per_m = 0;  // sigma(z) = sigma0_m + k_per_m z^2 (both >= 0)
  // Colour-depth offsets of the frames tracked: how many frames had one, their median and largest
  // absolute value [s].
  long offset_frames = 0;
  double offset_median_s = 0, offset_max_abs_s = 0;
  double sigma_at(double z_m) const { return sigma0_m + k_per_m * z_m * z_m; }
};

// One line for the run log: the curve, a few bins, the fit and the offsets.
std::string describe(const DepthNoiseEstimate& e);

class DepthNoiseEstimator {
 public:
  // bin_m: depth bin width [m] up to max_depth_m; cap_per_bin: the residuals kept per bin (the
  // newest; older ones are overwritten in order, so the estimate follows a changing scene).
  explicit DepthNoiseEstimator(double bin_m = 0.5, double max_depth_m = 6.0, std::size_t cap_per_bin = 4000);
  void add(double z_measured_m, double z_predicted_m);
  void add_offset(double depth_dt_s);  // one frame's colour-depth offset [s] (0: synchronised)
  DepthNoiseEstimate estimate(int min_per_bin = 50) const;

 private:
  struct Bin {
    std::vector<float> r;  // ring buffer of residuals [m]
    std::size_t next = 0;
  };
  double bin_m_;
  std::size_t cap_;
  std::vector<Bin> bins_;
  long samples_ = 0;
  std::vector<float> offsets_;  // non-zero offsets, one per frame (ring buffer like a bin)
  std::size_t next_offset_ = 0;
  long offset_frames_ = 0;
};

}  // namespace s3m::features
