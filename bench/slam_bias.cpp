// Stage-by-stage bias diagnostics of the RGB-D tracking front end against the simulator's exact
// truth (noise off by default): where would a systematic motion shrink come from?
//   bench_slam_bias [--scene office] [--trajectory uav_sweep] [--seed 13] [--frames 300]
//                   [--gap 5] [--step 10] [--noise]
// 1. keypoints: each keypoint with depth in frame i is back-projected with its own depth, moved
//    with the ground-truth relative pose into frame i+gap and projected; the best descriptor match
//    near the projection (same level) gives the offset measured - predicted per pyramid level:
//    mean signed du, dv and the radial slope (offset . r / |r|^2 about the principal point; a
//    coordinate-scaling bug shows as a non-zero slope), and the depth error against frame i+gap's
//    keypoint depth.
// 2. pose: the same matches (map points from frame i's keypoint depth, frame i at its true pose)
//    through the pose-only optimiser from a perturbed start: translation error along the true
//    motion (signed, relative) and its norm; the same solve without depth rows (pixels only); and
//    the summed chi2 of the estimate's inliers at the estimate and at the truth. A truth that costs
//    hardly more than an estimate centimetres away means a badly conditioned view (few, far,
//    coplanar points), not a biased measurement (--verbose: per pair).
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <map>
#include <string>
#include <vector>

#include "s3m/core/error.hpp"
#include "s3m/eval/align.hpp"
#include "s3m/features/orb_matcher.hpp"
#include "s3m/sim/simulate.hpp"
#include "s3m/slam/optim/bundle_adjustment.hpp"
#include "s3m/slam/optim/pose_optimizer.hpp"
#include "s3m/slam/slam_config.hpp"
#include "s3m/slam/system.hpp"

using namespace s3m;

namespace {

struct Args {
  sim::SimConfig sim;
  int gap = 5, step = 10;
  bool slam = false, verbose = false;
  double bf = 0;  // > 0: the SLAM's virtual baseline instead of the camera's
  std::string config;
};

Args parse(int argc, char** argv) {
  Args a;
  a.sim.scene = "office";
  a.sim.seed = 13;
  a.sim.sensor.noise = false;
  for (int i = 1; i < argc; ++i) {
    const std::string s = argv[i];
    auto next = [&]() { return std::string(argv[++i]); };
    if (s == "--scene")
      a.sim.scene = next();
    else if (s == "--trajectory")
      a.sim.trajectory.type = next();
    else if (s == "--seed")
      a.sim.seed = std::stoull(next());
    else if (s == "--frames")
      a.sim.trajectory.frames = std::stoi(next());
    else if (s == "--gap")
      a.gap = std::stoi(next());
    else if (s == "--step")
      a.step = std::stoi(next());
    else if (s == "--noise")
      a.sim.sensor.noise = true;
    else if (s == "--slam")
      a.slam = true;
    else if (s == "--verbose")
      a.verbose = true;
    else if (s == "--bf")
      a.bf = std::stod(next());
    else if (s == "--config")
      a.config = next();
    else
      throw s3m::Error("unknown option " + s);
  }
  return a;
}

struct PoseStats {
  int n = 0;
  double t_along = 0, t_err = 0, r_err = 0, t_err_mono = 0, r_err_mono = 0, chi2_est = 0, chi2_gt = 0;
};

double angle_deg(const SE3& a, const SE3& b) {
  return Eigen::AngleAxisd(a.linear().transpose() * b.linear()).angle() * 180 / M_PI;
}

// Stage 2 for one pair: frame b's pose from the matches, started at frame a's true pose.
void solve_pair(const std::vector<slam::PoseObservation>& obs, const SE3& T_wa, const SE3& T_wb,
                const PinholeCamera& cam, bool verbose, int pair, PoseStats& s) {
  const slam::PoseOptimizerConfig pc;
  const auto res = slam::optimize_pose(obs, T_wa.inverse(), cam, pc);
  const SE3 T_wb_est = res.T_c_w.inverse();
  double c_est = 0, c_gt = 0;
  for (std::size_t k = 0; k < obs.size(); ++k) {
    double c = 0;
    if (res.inlier[k] && slam::reprojection_chi2(obs[k], res.T_c_w, cam, c)) c_est += c;
    if (res.inlier[k] && slam::reprojection_chi2(obs[k], T_wb.inverse(), cam, c)) c_gt += c;
  }
  auto pixels_only = obs;
  for (auto& o : pixels_only) o.u_right = features::kNoRight;
  const SE3 T_wb_mono = slam::optimize_pose(pixels_only, T_wa.inverse(), cam, pc).T_c_w.inverse();
  const Vec3 d_gt = T_wb.translation() - T_wa.translation();
  const Vec3 d_est = T_wb_est.translation() - T_wa.translation();
  if (d_gt.norm() <= 1e-3) return;
  const double t_err = (T_wb_est.translation() - T_wb.translation()).norm();
  const double t_err_mono = (T_wb_mono.translation() - T_wb.translation()).norm();
  ++s.n;
  s.t_along += d_est.dot(d_gt) / d_gt.squaredNorm();
  s.t_err += t_err, s.r_err += angle_deg(T_wb_est, T_wb);
  s.t_err_mono += t_err_mono, s.r_err_mono += angle_deg(T_wb_mono, T_wb);
  s.chi2_est += c_est, s.chi2_gt += c_gt;
  if (verbose)
    std::printf(
        "pair %4d: %4zu matches, %4d inliers, chi2 at estimate %7.1f, at truth %7.1f | "
        "error %6.2f mm %.4f deg, pixels only %6.2f mm %.4f deg\n",
        pair, obs.size(), res.n_inliers, c_est, c_gt, 1e3 * t_err, angle_deg(T_wb_est, T_wb),
        1e3 * t_err_mono, angle_deg(T_wb_mono, T_wb));
}

struct LevelStats {
  int n = 0;
  double du = 0, dv = 0, rr = 0, rd = 0, dz_rel = 0, dz_abs = 0;
  int nz = 0;
};

// ATE (SE3) and Sim3 scale of est against gt positions.
void print_ate(const char* what, const std::vector<Vec3>& est, const std::vector<Vec3>& gt) {
  auto rmse = [&](eval::AlignMode m, double* scale) {
    const auto A = eval::align_positions(est, gt, m);
    double s = 0;
    for (std::size_t i = 0; i < est.size(); ++i) s += (A.apply(est[i]) - gt[i]).squaredNorm();
    if (scale) *scale = A.scale;
    return std::sqrt(s / est.size());
  };
  double scale = 1;
  const double se3 = rmse(eval::AlignMode::kSe3, nullptr), sim3 = rmse(eval::AlignMode::kSim3, &scale);
  std::printf("%-28s n %4zu  ATE se3 %.2f mm  sim3 %.2f mm  scale %.5f\n", what, est.size(), 1e3 * se3,
              1e3 * sim3, scale);
}

// 3. Whole SLAM (single thread) on the flight: tracking-time poses vs final poses vs keyframes.
void run_slam(const Args& a, const sim::Simulation& simu) {
  slam::SlamConfig cfg = a.config.empty() ? slam::SlamConfig{} : slam::load_slam_config(a.config);
  cfg.threaded = false;
  PinholeCamera cam = simu.camera();
  if (a.bf > 0) cam.bf = a.bf;
  slam::System sys(cam, cfg);
  std::vector<Vec3> track_est, track_gt;
  std::map<int, SE3> kf_track;
  for (std::size_t i = 0; i < simu.size(); ++i) {
    const auto r = sys.track(simu.frame(i));
    if (r.state != FrameState::kOk) continue;
    track_est.push_back(r.T_w_c.translation());
    track_gt.push_back(simu.trajectory().samples[i].T_w_c.translation());
    if (r.keyframe) kf_track[r.frame_index] = r.T_w_c;
    if (a.verbose) {
      const SE3 T_gt = simu.trajectory().samples[0].T_w_c.inverse() * simu.trajectory().samples[i].T_w_c;
      const Vec3 e = r.T_w_c.translation() - T_gt.translation();
      const double ang = Eigen::AngleAxisd(r.T_w_c.linear().transpose() * T_gt.linear()).angle() * 180 / M_PI;
      std::printf("frame %3zu%s inliers %4d  err (first-frame world) %+7.2f %+7.2f %+7.2f mm  rot %.3f deg",
                  i, r.keyframe ? "K" : " ", r.n_inliers, 1e3 * e.x(), 1e3 * e.y(), 1e3 * e.z(), ang);
      if (r.keyframe && sys.map().has_keyframe(sys.map().last_keyframe_id())) {
        const auto& kf = sys.map().keyframe(sys.map().last_keyframe_id());
        const Vec3 ek = kf.T_w_c.translation() - T_gt.translation();
        int n_pts = 0;
        for (auto pid : kf.points) n_pts += pid != slam::kNoId;
        std::printf("  after BA %+7.2f %+7.2f %+7.2f mm, %d points", 1e3 * ek.x(), 1e3 * ek.y(), 1e3 * ek.z(),
                    n_pts);
      }
      std::printf("\n");
    }
  }
  sys.finish();
  std::vector<Vec3> fin_est, fin_gt, kf_est, kf_gt, kft_est, kft_gt;
  for (const auto& p : sys.camera_trajectory()) {
    fin_est.push_back(p.T_w_x.translation());
    fin_gt.push_back(simu.trajectory().samples[p.frame_index].T_w_c.translation());
  }
  for (const auto& p : sys.keyframe_trajectory()) {
    kf_est.push_back(p.T_w_x.translation());
    kf_gt.push_back(simu.trajectory().samples[p.frame_index].T_w_c.translation());
    kft_est.push_back(kf_track.at(p.frame_index).translation());
    kft_gt.push_back(kf_gt.back());
  }
  // The final map's observations with every keyframe held at (a) its estimated and (b) its true pose,
  // points re-optimised: which poses do the measurements prefer?
  for (int use_gt = 0; use_gt < 2; ++use_gt) {
    slam::BaProblem P;
    std::map<KeyframeId, int> fi;
    const SE3 T_0w =
        simu.trajectory().samples[sys.map().keyframes().begin()->second.frame_index].T_w_c.inverse();
    for (const auto& [id, kf] : sys.map().keyframes()) {
      fi[id] = static_cast<int>(P.T_c_w.size());
      P.T_c_w.push_back(use_gt ? (T_0w * simu.trajectory().samples[kf.frame_index].T_w_c).inverse()
                               : kf.T_w_c.inverse());
      P.fixed.push_back(1);
    }
    for (const auto& [pid, mp] : sys.map().points()) {
      if (mp.observations.size() < 2) continue;
      P.p_w.push_back(mp.p_w);
      for (const auto& [kid, idx] : mp.observations) {
        const auto& k = sys.map().keyframe(kid);
        const auto& kp = k.features->keypoints[idx];
        slam::BaObservation o;
        o.frame = fi.at(kid);
        o.point = static_cast<int>(P.p_w.size()) - 1;
        o.uv = {kp.pt.x, kp.pt.y};
        o.u_right = k.features->u_right[idx];
        o.inv_sigma2 = k.features->pyramid.inv_sigma2[kp.octave];
        P.obs.push_back(o);
      }
    }
    slam::BaConfig bc;
    const auto res = slam::bundle_adjust(P, cam, bc);
    double chi2_mono = 0, chi2_depth = 0;
    int n = 0;
    for (std::size_t k = 0; k < P.obs.size(); ++k) {
      if (res.outlier[k]) continue;
      const auto& o = P.obs[k];
      const Vec3 pc = P.T_c_w[o.frame] * P.p_w[o.point];
      const double u = cam.fx * pc.x() / pc.z() + cam.cx, v = cam.fy * pc.y() / pc.z() + cam.cy;
      chi2_mono += ((u - o.uv.x()) * (u - o.uv.x()) + (v - o.uv.y()) * (v - o.uv.y())) * o.inv_sigma2;
      if (features::has_right(o.u_right))
        chi2_depth += std::pow(u - cam.bf / pc.z() - o.u_right, 2) * o.inv_sigma2;
      ++n;
    }
    std::printf(
        "map, keyframes fixed at %s poses: %zu obs, %d outliers, mean chi2 image %.4f depth row %.4f\n",
        use_gt ? "TRUE" : "estimated", P.obs.size(), res.n_outliers, chi2_mono / n, chi2_depth / n);
  }
  print_ate("frames at tracking time", track_est, track_gt);
  print_ate("frames, final", fin_est, fin_gt);
  print_ate("keyframes at tracking time", kft_est, kft_gt);
  print_ate("keyframes, final", kf_est, kf_gt);
}

}  // namespace

int main(int argc, char** argv) try {
  const Args a = parse(argc, argv);
  const sim::Simulation simu(a.sim);
  if (a.slam) {
    run_slam(a, simu);
    return 0;
  }
  const PinholeCamera& cam = simu.camera();
  features::FeatureConfig fc;
  const features::OrbExtractor extractor(fc.orb);
  std::map<int, LevelStats> lv;
  PoseStats ps;
  for (int i = 0; i + a.gap < static_cast<int>(simu.size()); i += a.step) {
    const RgbdFrame fa = simu.frame(i), fb = simu.frame(i + a.gap);
    const auto A = features::compute_frame_features(fa.rgb, fa.depth_m, cam, extractor, fc);
    const auto B = features::compute_frame_features(fb.rgb, fb.depth_m, cam, extractor, fc);
    const SE3 T_wa = simu.trajectory().samples[i].T_w_c, T_wb = simu.trajectory().samples[i + a.gap].T_w_c;
    const SE3 T_ba = T_wb.inverse() * T_wa;
    std::vector<slam::PoseObservation> obs;
    for (int k = 0; k < A.size(); ++k) {
      if (!A.has_depth(k)) continue;
      const auto& kp = A.keypoints[k];
      const Vec3 p_b = T_ba * cam.backproject(kp.pt.x, kp.pt.y, A.depth_m[k]);
      if (p_b.z() < 0.1) continue;
      const Eigen::Vector2d uv = cam.project(p_b);
      int best = -1, bd = 60;
      for (int j : B.in_area(uv.x(), uv.y(), 6.0, kp.octave, kp.octave)) {
        const int d = features::descriptor_distance(A.descriptor(k), B.descriptor(j));
        if (d < bd) bd = d, best = j;
      }
      if (best < 0) continue;
      const auto& kb = B.keypoints[best];
      const double du = kb.pt.x - uv.x(), dv = kb.pt.y - uv.y();
      const double rx = uv.x() - cam.cx, ry = uv.y() - cam.cy;
      auto& s = lv[kp.octave];
      ++s.n;
      s.du += du, s.dv += dv, s.rd += du * rx + dv * ry, s.rr += rx * rx + ry * ry;
      if (B.has_depth(best)) {
        ++s.nz;
        s.dz_rel += (B.depth_m[best] - p_b.z()) / p_b.z();
        s.dz_abs += std::abs(B.depth_m[best] - p_b.z());
      }
      slam::PoseObservation o =
          slam::keypoint_observation(B, best, T_wa * cam.backproject(kp.pt.x, kp.pt.y, A.depth_m[k]));
      obs.push_back(o);
    }
    if (obs.size() < 20) continue;
    solve_pair(obs, T_wa, T_wb, cam, a.verbose, i, ps);
  }
  std::printf("level      n    mean du     mean dv   radial slope  |  n depth  mean dz/z   mean |dz| mm\n");
  for (const auto& [l, s] : lv)
    std::printf("%5d %6d %+10.4f %+10.4f %+12.5f   | %7d %+10.5f %10.2f\n", l, s.n, s.du / s.n, s.dv / s.n,
                s.rd / s.rr, s.nz, s.nz ? s.dz_rel / s.nz : 0.0, s.nz ? 1e3 * s.dz_abs / s.nz : 0.0);
  const double n = std::max(1, ps.n);
  std::printf(
      "pose-only over %d pairs (gap %d): translation along the true motion %.5f (1 = exact), "
      "mean |dt| %.2f mm, mean rotation error %.4f deg; pixels only: %.2f mm, %.4f deg; "
      "chi2 of the inliers at the estimate %.1f, at the truth %.1f (mean per pair)\n",
      ps.n, a.gap, ps.t_along / n, 1e3 * ps.t_err / n, ps.r_err / n, 1e3 * ps.t_err_mono / n,
      ps.r_err_mono / n, ps.chi2_est / n, ps.chi2_gt / n);
  return 0;
} catch (const std::exception& e) {
  std::fprintf(stderr, "bench_slam_bias: %s\n", e.what());
  return 1;
}
