// Measures how an unregistered depth image lines up with its colour image, from the images alone
// (no trajectory, no SLAM): depth discontinuities (object borders) must fall on colour edges. For a
// model "depth pixel = c_d + s * (colour pixel - c) + (dx, dy)" it finds the scale s and shift
// (dx, dy) [px] that minimise the mean truncated distance from every depth edge to the nearest
// colour (Canny) edge, over frames 0, step, 2*step, ... of a TUM-layout sequence.
//   bench_depth_registration DATASET_DIR [--frames N] [--step K] [--time-offset] [--gt-offset GAP]
//       [--time-offset-frames FIRST LAST]
// s = f_depth / f_colour when both cameras share the principal point; (dx, dy) then absorbs the
// depth-colour baseline at the scene's typical depth (f_d * b / z). A second fit uses the baseline
// model (shift f_d * b / z per edge, z known there). Then, independently of the colour image, it
// checks which depth focal length and depth scale the ground truth is consistent with: depth
// pixels of frame i moved by the ground-truth relative pose must land on frame i+15's depth.
// --time-offset: which depth frame each colour frame is nearest in time to (an unsynchronised
// Kinect pairs its two streams by index); --gt-offset GAP: which frame index the ground-truth poses
// belong to, from the depth images alone; --time-offset-frames: the same as --time-offset, per colour frame.
// Results on 7-Scenes redkitchen: docs/RESULTS.md, SLAM.
#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

#include <opencv2/imgproc.hpp>

#include "s3m/features/depth_registration.hpp"
#include "s3m/io/tum_dataset.hpp"

using namespace s3m;

namespace {

// The edges and their distance are the library's (features/depth_registration.hpp), so this bench
// measures what `s3m run` decides on; the fit below is its own denser grid (3000 edges per frame).
using features::EdgeFrame;
using features::colour_edge_distance;

EdgeFrame edges_of(const cv::Mat& dist_colour, const cv::Mat& depth_m) {
  return features::edge_frame(dist_colour, depth_m, 3000);
}

double cost(const std::vector<EdgeFrame>& frames, double s, double dx, double dy, double cx, double cy,
            double fb = 0) {
  return features::edge_distance(frames, s, dx, dy, cx, cy, fb);
}

struct Registration {
  double s = 1, dx = 0, dy = 0, cost = 1e18;
};

// Coarse-to-fine grid search over (s, dx, dy).
Registration fit_registration(const std::vector<EdgeFrame>& frames, double cx, double cy) {
  Registration r;
  for (double s = 0.90; s <= 1.25; s += 0.01)
    for (double dx = -20; dx <= 20; dx += 2)
      for (double dy = -20; dy <= 20; dy += 2)
        if (const double c = cost(frames, s, dx, dy, cx, cy); c < r.cost) r = {s, dx, dy, c};
  const Registration coarse = r;
  for (double s = coarse.s - 0.01; s <= coarse.s + 0.01; s += 0.001)
    for (double dx = coarse.dx - 2; dx <= coarse.dx + 2; dx += 0.25)
      for (double dy = coarse.dy - 2; dy <= coarse.dy + 2; dy += 0.25)
        if (const double c = cost(frames, s, dx, dy, cx, cy); c < r.cost) r = {s, dx, dy, c};
  return r;
}

// Colour-depth time offset from the images alone: a Kinect v1 runs its two cameras unsynchronised,
// and 7-Scenes pairs them by index. Colour frame i is compared with depth frame i + k for
// k = -2..2, each pairing with its own registration fit (so a constant shift cannot stand in for
// the motion); the pairing whose depth edges fall closest to the colour edges is the one nearest in
// time, and a parabola through the three best costs gives the sub-frame offset. Frames are taken
// every `step` from 2 to size - 3, so every pairing uses the same colour images.
void measure_time_offset(const io::TumDataset& ds, int n_frames, int step) {
  const double cx = ds.camera().cx, cy = ds.camera().cy;
  std::vector<std::size_t> index;
  std::vector<cv::Mat> dist;  // the colour images' edge distances, the same for every pairing
  for (int j = 0; j < n_frames; ++j) {
    const std::size_t i = 2 + static_cast<std::size_t>(j * step);
    if (i + 2 >= ds.size()) break;
    index.push_back(i);
    dist.push_back(colour_edge_distance(ds.load(i).rgb));
  }
  std::vector<double> costs;
  for (int k = -2; k <= 2; ++k) {
    std::vector<EdgeFrame> frames;
    for (std::size_t j = 0; j < index.size(); ++j) frames.push_back(edges_of(dist[j], ds.load(index[j] + k).depth_m));
    const Registration r = fit_registration(frames, cx, cy);
    costs.push_back(r.cost);
    std::printf("time offset: colour i with depth i%+d (%zu frames): scale %.3f  dx %.2f  dy %.2f px  "
                "mean edge distance %.3f px\n",
                k, frames.size(), r.s, r.dx, r.dy, r.cost);
  }
  std::size_t b = 1;
  for (std::size_t k = 1; k + 1 < costs.size(); ++k)
    if (costs[k] < costs[b]) b = k;
  const double denom = costs[b - 1] - 2 * costs[b] + costs[b + 1];
  const double frac = denom > 0 ? 0.5 * (costs[b - 1] - costs[b + 1]) / denom : 0.0;
  std::printf("time offset: colour frame i is nearest in time to depth frame i%+.2f\n",
              static_cast<double>(b) - 2 + frac);
}

// Per colour frame i in [first, last]: the mean edge distance to depth frames i-3..i+3 under one
// registration (the k = 0 fit of measure_time_offset over the whole sequence), so single frames
// captured at another instant than their index says stand out.
void time_offset_per_frame(const io::TumDataset& ds, int first, int last, const Registration& r) {
  const double cx = ds.camera().cx, cy = ds.camera().cy;
  for (int i = std::max(first, 3); i <= last && static_cast<std::size_t>(i + 3) < ds.size(); ++i) {
    const cv::Mat dist = colour_edge_distance(ds.load(static_cast<std::size_t>(i)).rgb);
    std::printf("colour %d:", i);
    int best_k = 0;
    double best = 1e18;
    for (int k = -3; k <= 3; ++k) {
      const std::vector<EdgeFrame> f{edges_of(dist, ds.load(static_cast<std::size_t>(i + k)).depth_m)};
      const double e = cost(f, r.s, r.dx, r.dy, cx, cy);
      std::printf(" %+d:%.2f", k, e);
      if (e < best) best = e, best_k = k;
    }
    std::printf("  -> depth %d\n", i + best_k);
  }
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

// Whether the ground truth's frame indices match the depth images': depth frame i and frame
// i + gap, moved by the ground-truth poses of frames i + k and i + gap + k, for k = -2..2. The
// residual is smallest at the k whose poses belong to those depth images (KinectFusion made the
// ground truth from exactly these depth images).
void measure_gt_offset(const io::TumDataset& ds, int gap) {
  // Each pair's depth images are read once; only the poses attached to them change with k.
  struct DepthPair {
    std::size_t i;
    RgbdFrame a, b;  // depth only
  };
  std::vector<DepthPair> pairs;
  for (std::size_t i = 2; i + gap + 2 < ds.size(); i += 2 * gap + 1) {
    DepthPair p{i, {}, {}};
    p.a.depth_m = ds.load(i).depth_m;
    p.b.depth_m = ds.load(i + gap).depth_m;
    pairs.push_back(std::move(p));
  }
  for (int k = -2; k <= 2; ++k) {
    double sum = 0;
    int n = 0;
    for (const auto& p : pairs) {
      const auto Ti = ds.groundtruth_at(ds.timestamp(p.i + k)), Tj = ds.groundtruth_at(ds.timestamp(p.i + gap + k));
      if (!Ti || !Tj) continue;
      sum += gt_depth_residual(ds, {{p.a, *Ti}, {p.b, *Tj}}, 585, 1);
      ++n;
    }
    std::printf("depth frames i, i+%d with ground-truth poses of i%+d, i+%d%+d (%d pairs): mean depth residual %.3f mm\n",
                gap, k, gap, k, n, n ? 1000 * sum / n : 0.0);
  }
}

}  // namespace

int main(int argc, char** argv) {
  if (argc < 2) {
    std::fprintf(stderr, "usage: bench_depth_registration DATASET_DIR [--frames N] [--step K] [--time-offset] [--gt-offset GAP] [--time-offset-frames FIRST LAST]\n");
    return 2;
  }
  int n_frames = 10, step = 50;
  bool time_offset_only = false;
  int gt_offset_gap = 0, per_first = -1, per_last = -1;
  for (int i = 2; i < argc; ++i) {
    const std::string a = argv[i];
    if (a == "--time-offset") time_offset_only = true;
    else if (a == "--gt-offset" && i + 1 < argc) gt_offset_gap = std::stoi(argv[++i]);
    else if (a == "--time-offset-frames" && i + 2 < argc) per_first = std::stoi(argv[++i]), per_last = std::stoi(argv[++i]);
    else if (a == "--frames" && i + 1 < argc) n_frames = std::stoi(argv[++i]);
    else if (a == "--step" && i + 1 < argc) step = std::stoi(argv[++i]);
  }
  try {
    const auto ds = io::TumDataset::open(argv[1]);
    if (per_first >= 0) {
      // The registration measure_time_offset fits at k = 0 (--frames 50 --step 9).
      time_offset_per_frame(ds, per_first, per_last, Registration{1.104, 9.25, 1.75, 0});
      return 0;
    }
    if (gt_offset_gap > 0) {
      measure_gt_offset(ds, gt_offset_gap);
      return 0;
    }
    if (time_offset_only) {
      measure_time_offset(ds, n_frames, step);
      return 0;
    }
    const double cx = ds.camera().cx, cy = ds.camera().cy;
    std::vector<EdgeFrame> frames;
    for (int k = 0; k < n_frames && static_cast<std::size_t>(k * step) < ds.size(); ++k) {
      const RgbdFrame f = ds.load(static_cast<std::size_t>(k * step));
      frames.push_back(edges_of(colour_edge_distance(f.rgb), f.depth_m));
    }
    const Registration reg = fit_registration(frames, cx, cy);
    const double bs = reg.s, bdx = reg.dx, bdy = reg.dy, best = reg.cost;
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
