// Measures how an unregistered depth image lines up with its colour image, from the images alone
// (no trajectory, no SLAM): depth discontinuities (object borders) must fall on colour edges. For a
// model "depth pixel = c_d + s * (colour pixel - c) + (dx, dy)" it finds the scale s and shift
// (dx, dy) [px] that minimise the mean truncated distance from every depth edge to the nearest
// colour (Canny) edge, over frames 0, step, 2*step, ... of a TUM-layout sequence.
//   bench_depth_registration DATASET_DIR [--frames N] [--step K]
// s = f_depth / f_colour when both cameras share the principal point; (dx, dy) then absorbs the
// depth-colour baseline at the scene's typical depth (f_d * b / z). A second fit uses the baseline
// model (shift f_d * b / z per edge, z known there). Then, independently of the colour image, it
// checks which depth focal length and depth scale the ground truth is consistent with: depth
// pixels of frame i moved by the ground-truth relative pose must land on frame i+15's depth.
// Results on 7-Scenes redkitchen: docs/RESULTS.md, SLAM.
#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

#include <opencv2/imgproc.hpp>

#include "s3m/io/tum_dataset.hpp"

using namespace s3m;

namespace {

struct EdgeFrame {
  cv::Mat dist_colour;                    // CV_32F distance to the nearest colour edge [px]
  std::vector<cv::Point2f> depth_edges;  // depth-image pixels on a depth discontinuity
  std::vector<float> edge_z;             // their depth [m]
};

EdgeFrame edges_of(const RgbdFrame& f) {
  EdgeFrame e;
  cv::Mat gray, canny;
  cv::cvtColor(f.rgb, gray, cv::COLOR_BGR2GRAY);
  cv::GaussianBlur(gray, gray, cv::Size(5, 5), 1.2);
  cv::Canny(gray, canny, 40, 100);
  cv::distanceTransform(255 - canny, e.dist_colour, cv::DIST_L2, 3);
  // A depth edge: the nearer side of a jump of more than 10 % of the depth to a neighbour (the
  // object border, where the colour edge is too).
  const cv::Mat& d = f.depth_m;
  for (int y = 1; y + 1 < d.rows; ++y)
    for (int x = 1; x + 1 < d.cols; ++x) {
      const float z = d.at<float>(y, x);
      if (!(z > 0.3f)) continue;
      const float nb[4] = {d.at<float>(y, x + 1), d.at<float>(y, x - 1), d.at<float>(y + 1, x), d.at<float>(y - 1, x)};
      for (float n : nb)
        if (n > 0 && n - z > 0.1f * z) {
          e.depth_edges.emplace_back(float(x), float(y));
          e.edge_z.push_back(z);
          break;
        }
    }
  // Every k-th edge pixel is plenty for a 3-parameter fit and keeps the grid search fast.
  const std::size_t k = e.depth_edges.size() / 3000 + 1;
  std::vector<cv::Point2f> sub;
  std::vector<float> sub_z;
  for (std::size_t i = 0; i < e.depth_edges.size(); i += k) sub.push_back(e.depth_edges[i]), sub_z.push_back(e.edge_z[i]);
  e.depth_edges.swap(sub);
  e.edge_z.swap(sub_z);
  return e;
}

// fb: depth-dependent shift f_d * b [px m] (the baseline model), added to the constant dx.
double cost(const std::vector<EdgeFrame>& frames, double s, double dx, double dy, double cx, double cy,
            double fb = 0) {
  constexpr double kTruncPx = 8.0;
  double sum = 0;
  long n = 0;
  for (const auto& f : frames)
    for (std::size_t i = 0; i < f.depth_edges.size(); ++i) {
      const auto& p = f.depth_edges[i];
      // Inverse of the model: colour pixel of this depth pixel.
      const double u = cx + (p.x - cx - dx - fb / f.edge_z[i]) / s, v = cy + (p.y - cy - dy) / s;
      const int iu = static_cast<int>(std::lround(u)), iv = static_cast<int>(std::lround(v));
      if (iu < 0 || iv < 0 || iu >= f.dist_colour.cols || iv >= f.dist_colour.rows) continue;
      sum += std::min(kTruncPx, static_cast<double>(f.dist_colour.at<float>(iv, iu)));
      ++n;
    }
  return n ? sum / n : 1e9;
}

// Mean truncated depth residual [m] when depth pixels of frame i, back-projected with focal f [px]
// and moved by the ground-truth relative pose, are compared with frame j's depth: ground truth
// made with the depth camera's intrinsics is most consistent at that camera's f.
// depth_scale multiplies every depth (a depth-scale error of the ground truth would show as a
// minimum away from 1).
double gt_depth_residual(const io::TumDataset& ds, const std::vector<std::pair<RgbdFrame, SE3>>& frames, double f,
                         int gap, double depth_scale = 1.0) {
  const double cx = ds.camera().cx, cy = ds.camera().cy;
  double sum = 0;
  long n = 0;
  for (std::size_t k = 0; k + gap < frames.size(); k += gap) {
    const auto& [fi, Ti] = frames[k];
    const auto& [fj, Tj] = frames[k + gap];
    const SE3 T_j_i = Tj.inverse() * Ti;
    for (int v = 0; v < fi.depth_m.rows; v += 4)
      for (int u = 0; u < fi.depth_m.cols; u += 4) {
        const double z = depth_scale * fi.depth_m.at<float>(v, u);
        if (!(z > 0.3 && z < 4.0)) continue;
        const Vec3 p = T_j_i * Vec3((u - cx) * z / f, (v - cy) * z / f, z);
        if (p.z() < 0.3) continue;
        const int uj = static_cast<int>(std::lround(f * p.x() / p.z() + cx));
        const int vj = static_cast<int>(std::lround(f * p.y() / p.z() + cy));
        if (uj < 0 || vj < 0 || uj >= fj.depth_m.cols || vj >= fj.depth_m.rows) continue;
        const double zj = depth_scale * fj.depth_m.at<float>(vj, uj);
        if (!(zj > 0.3)) continue;
        sum += std::min(0.05, std::abs(p.z() - zj));
        ++n;
      }
  }
  return n ? sum / n : 1e9;
}

}  // namespace

int main(int argc, char** argv) {
  if (argc < 2) {
    std::fprintf(stderr, "usage: bench_depth_registration DATASET_DIR [--frames N] [--step K]\n");
    return 2;
  }
  int n_frames = 10, step = 50;
  for (int i = 2; i + 1 < argc; i += 2) {
    const std::string a = argv[i];
    if (a == "--frames") n_frames = std::stoi(argv[i + 1]);
    else if (a == "--step") step = std::stoi(argv[i + 1]);
  }
  try {
    const auto ds = io::TumDataset::open(argv[1]);
    const double cx = ds.camera().cx, cy = ds.camera().cy;
    std::vector<EdgeFrame> frames;
    for (int k = 0; k < n_frames && static_cast<std::size_t>(k * step) < ds.size(); ++k)
      frames.push_back(edges_of(ds.load(static_cast<std::size_t>(k * step))));
    // Coarse-to-fine grid search over (s, dx, dy).
    double best = 1e18, bs = 1, bdx = 0, bdy = 0;
    for (double s = 0.90; s <= 1.25; s += 0.01)
      for (double dx = -20; dx <= 20; dx += 2)
        for (double dy = -20; dy <= 20; dy += 2)
          if (const double c = cost(frames, s, dx, dy, cx, cy); c < best) best = c, bs = s, bdx = dx, bdy = dy;
    const double s0 = bs, dx0 = bdx, dy0 = bdy;
    for (double s = s0 - 0.01; s <= s0 + 0.01; s += 0.001)
      for (double dx = dx0 - 2; dx <= dx0 + 2; dx += 0.25)
        for (double dy = dy0 - 2; dy <= dy0 + 2; dy += 0.25)
          if (const double c = cost(frames, s, dx, dy, cx, cy); c < best) best = c, bs = s, bdx = dx, bdy = dy;
    std::printf("frames %zu  best: scale %.3f  dx %.2f px  dy %.2f px  mean edge distance %.3f px\n", frames.size(),
                bs, bdx, bdy, best);
    std::printf("identity (registered) model: mean edge distance %.3f px\n", cost(frames, 1, 0, 0, cx, cy));
    std::printf("scale 585/525 = %.4f, no shift: %.3f px\n", 585.0 / 525.0, cost(frames, 585.0 / 525.0, 0, 0, cx, cy));
    for (double s : {1.0, 1.05, 1.1, 1.114, 1.15}) {
      double b = 1e18;
      for (double dx = -20; dx <= 20; dx += 0.5)
        for (double dy = -20; dy <= 20; dy += 0.5) b = std::min(b, cost(frames, s, dx, dy, cx, cy));
      std::printf("  scale %.3f, best shift: %.3f px\n", s, b);
    }
    // Which depth focal length is the ground truth consistent with?
    std::vector<std::pair<RgbdFrame, SE3>> gt_frames;
    for (std::size_t i = 0; i < ds.size() && gt_frames.size() < 40; i += 5)
      if (const auto T = ds.groundtruth_at(ds.timestamp(i))) gt_frames.emplace_back(ds.load(i), *T);
    for (double f = 525; f <= 665; f += 10)
      std::printf("ground truth vs depth, f %.0f px: mean depth residual %.2f mm\n", f,
                  1000 * gt_depth_residual(ds, gt_frames, f, 3));
    for (double k = 0.95; k <= 1.0501; k += 0.01)
      std::printf("ground truth vs depth, f 585 px, depth x %.2f: mean depth residual %.2f mm\n", k,
                  1000 * gt_depth_residual(ds, gt_frames, 585, 3, k));
    // Baseline model: shift f_d * b / z per edge (z known at depth edges), no constant dx.
    const double fd = 585.0;  // the 7-Scenes depth-camera focal length [px]
    double bb = 1e18, b_s = 1, b_b = 0, b_dy = 0;
    for (double s = 1.08; s <= 1.13; s += 0.0025)
      for (double b = 0.0; b <= 0.05; b += 0.0025)
        for (double dy = -3; dy <= 3; dy += 0.5)
          if (const double c = cost(frames, s, 0, dy, cx, cy, fd * b); c < bb) bb = c, b_s = s, b_b = b, b_dy = dy;
    std::printf("baseline model (f_d = %.0f px): scale %.4f  baseline %.4f m  dy %.2f px  mean edge distance %.3f px\n",
                fd, b_s, b_b, b_dy, bb);
    std::printf("  at scale 585/525, dy 0, baseline 0.025 m: %.3f px\n",
                cost(frames, 585.0 / 525.0, 0, 0, cx, cy, fd * 0.025));
  } catch (const std::exception& e) {
    std::fprintf(stderr, "error: %s\n", e.what());
    return 1;
  }
  return 0;
}
