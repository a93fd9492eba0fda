// How well the tracker's fallback for lost frames (slam::DepthOdometry, OpenCV rgbd's
// RgbdICPOdometry) measures frame-to-frame motion on a recording with ground truth, next to the
// constant-velocity guess it replaces: per consecutive frame pair, the rotation and translation
// error of each against the ground-truth motion, and what fraction the tracker's agreement check
// (tracker.odometry_deg / odometry_m) would accept. The odometry starts from
// the velocity of the ground truth's previous step, as the tracker starts from its last velocity;
// a measurement the velocity disagrees with is accepted when the same alignment started from no
// motion lands on it (the tracker's rule).
//   bench_depth_odometry DATASET_DIR [--first N] [--frames N] [--downsample K]
// Results (simulator rows, 7-Scenes redkitchen): docs/RESULTS.md, issue 20 session 11.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

#include "s3m/core/error.hpp"
#include "s3m/io/tum_dataset.hpp"
#include "s3m/slam/odometry/depth_odometry.hpp"
#include "s3m/slam/tracking/tracker.hpp"

namespace {

using namespace s3m;

struct Errors {
  std::vector<double> deg, mm;
  void add(const SE3& e) {
    deg.push_back(rotation_angle_rad(e.linear()) * 180.0 / M_PI);
    mm.push_back(1000.0 * e.translation().norm());
  }
};

double percentile(std::vector<double> v, double q) {
  if (v.empty()) return NAN;
  std::sort(v.begin(), v.end());
  return v[std::min(v.size() - 1, static_cast<std::size_t>(q * double(v.size())))];
}

void print(const char* what, const Errors& e) {
  std::printf(
      "%-34s %5zu pairs  rotation median %.3f / p90 %.3f / max %.3f deg  translation median %.2f / p90 %.2f "
      "/ "
      "max %.2f mm\n",
      what, e.deg.size(), percentile(e.deg, 0.5), percentile(e.deg, 0.9), percentile(e.deg, 1.0),
      percentile(e.mm, 0.5), percentile(e.mm, 0.9), percentile(e.mm, 1.0));
}

}  // namespace

int main(int argc, char** argv) {
  if (argc < 2) {
    std::fprintf(stderr,
                 "usage: bench_depth_odometry DATASET_DIR [--first N] [--frames N] [--downsample K]\n");
    return 2;
  }
  int first = 1, frames = 300;
  const slam::TrackerConfig tracker;  // the agreement check's defaults
  slam::DepthOdometryConfig config;
  for (int i = 2; i + 1 < argc; i += 2) {
    const std::string a = argv[i];
    if (a == "--first")
      first = std::max(1, std::stoi(argv[i + 1]));
    else if (a == "--frames")
      frames = std::stoi(argv[i + 1]);
    else if (a == "--downsample")
      config.downsample = std::stoi(argv[i + 1]);
  }
  try {
    const auto ds = io::TumDataset::open(argv[1]);
    const slam::DepthOdometry odometry(ds.camera(), config);
    Errors velocity, measured, accepted;
    int failed = 0, restarted = 0;
    RgbdFrame prev = ds.load(static_cast<std::size_t>(first));
    for (std::size_t i = first + 1; i < ds.size() && int(i) <= first + frames; ++i) {
      RgbdFrame cur = ds.load(i);
      const auto T0 = ds.groundtruth_at(ds.timestamp(i - 2)), T1 = ds.groundtruth_at(ds.timestamp(i - 1)),
                 T2 = ds.groundtruth_at(ds.timestamp(i));
      if (T0 && T1 && T2) {
        const SE3 truth = T2->inverse() * *T1, guess = T1->inverse() * *T0;  // T_cur_prev, T_prev_prevprev
        velocity.add(guess * truth.inverse());
        if (const auto m = odometry.align(prev, cur, guess)) {
          measured.add(*m * truth.inverse());
          // The tracker's rule (tracker_lost.cpp): agreement with the velocity, else with a restart.
          bool ok = s3m::poses_agree(*m, guess, tracker.dead_reckoning.odometry_deg,
                                     tracker.dead_reckoning.odometry_m);
          if (!ok) {
            const auto again = odometry.align(prev, cur, SE3::Identity());
            ok = again && s3m::poses_agree(*m, *again, tracker.dead_reckoning.odometry_deg,
                                           tracker.dead_reckoning.odometry_m);
            restarted += ok;
          }
          if (ok) accepted.add(*m * truth.inverse());
        } else {
          ++failed;
        }
      }
      prev = std::move(cur);
    }
    std::printf("%s: frames %d-%d, odometry at 1/%d resolution\n", argv[1], first, first + frames,
                config.downsample);
    print("constant velocity (ground truth's)", velocity);
    print("depth odometry", measured);
    print("... accepted by the agreement check", accepted);
    std::printf(
        "depth odometry did not converge on %d pairs; %d accepted only by the restart from no motion\n",
        failed, restarted);
  } catch (const Error& e) {
    std::fprintf(stderr, "bench_depth_odometry: %s\n", e.what());
    return 1;
  }
  return 0;
}
