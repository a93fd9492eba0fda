// Time of io::DepthToColour per frame for RealSense D4xx stream sizes: 848x480 depth (fx 425)
// drawn into 640x480 (fx 615) or 1280x720 (fx 910) colour, 1.5 cm apart, with and without colour
// distortion; and 7-Scenes' Kinect v1 (640x480 depth, 585 px, into 640x480 colour, 529 px, 2.5 cm
// apart; camera preset 7scenes_kinect_v1). The depth image is a slanted wall with boxes in front
// (every pixel valid).
//   build/bench/bench_depth_to_colour [--benchmark_repetitions=3]
#include <benchmark/benchmark.h>

#include "s3m/io/depth_to_colour.hpp"

namespace {

using s3m::PinholeCamera;

PinholeCamera camera(double f, int w, int h) {
  PinholeCamera c;
  c.fx = c.fy = f, c.cx = (w - 1) / 2.0, c.cy = (h - 1) / 2.0, c.width = w, c.height = h;
  return c;
}

cv::Mat scene(int w, int h) {
  cv::Mat d(h, w, CV_32FC1);
  for (int v = 0; v < h; ++v)
    for (int u = 0; u < w; ++u) d.at<float>(v, u) = 1.5f + 2.0f * u / w + ((u / 80 + v / 60) % 3 == 0 ? -0.8f : 0.0f);
  return d;
}

void BM_DepthToColour(benchmark::State& state) {
  if (state.range(0) == 2) {  // 7-Scenes' Kinect v1
    s3m::SE3 T_c_d = s3m::SE3::Identity();
    T_c_d.translation() = s3m::Vec3(-0.025, 0, 0);
    const s3m::io::DepthToColour to_colour(camera(585, 640, 480), camera(529, 640, 480), T_c_d);
    const cv::Mat depth = scene(640, 480);
    for (auto _ : state) benchmark::DoNotOptimize(to_colour(depth));
    state.SetLabel("Kinect v1 640x480 585 px -> 640x480 529 px");
    return;
  }
  const bool hd = state.range(0) != 0, distorted = state.range(1) != 0;
  PinholeCamera colour = hd ? camera(910, 1280, 720) : camera(615, 640, 480);
  if (distorted) colour.dist = {0.06, -0.08, 0.0004, -0.0009, 0.03};
  s3m::SE3 T_c_d = s3m::SE3::Identity();
  T_c_d.translation() = s3m::Vec3(-0.015, 0, 0);
  const s3m::io::DepthToColour to_colour(camera(425, 848, 480), colour, T_c_d);
  const cv::Mat depth = scene(848, 480);
  for (auto _ : state) benchmark::DoNotOptimize(to_colour(depth));
  state.SetLabel(std::string(hd ? "848x480 -> 1280x720" : "848x480 -> 640x480") + (distorted ? ", distorted" : ""));
}
BENCHMARK(BM_DepthToColour)->Args({0, 0})->Args({0, 1})->Args({1, 0})->Args({1, 1})->Args({2, 0})->Unit(benchmark::kMillisecond);

}  // namespace

BENCHMARK_MAIN();
