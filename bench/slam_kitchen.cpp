// RGB-D SLAM on a TUM-layout sequence (default: the 7-Scenes redkitchen 500-frame excerpt).
// Prints ATE RMSE (SE3 Umeyama alignment), RPE (1-frame and 1-s), tracking ms/frame, lost frames.
//   bench_slam_kitchen [DATASET_DIR] [--threaded] [--config FILE] [--out DIR] [--depth-factor F]
// DATASET_DIR defaults to $S3M_KITCHEN_DIR. Intrinsics from DATASET_DIR/camera.yaml.
// Self-contained loader and ATE so it runs before io/eval land; it reads only TUM-layout files.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>
#include <string>
#include <vector>

#include <opencv2/imgcodecs.hpp>

#include "s3m/core/timing.hpp"
#include "s3m/core/yaml_util.hpp"
#include "s3m/slam/system.hpp"

using namespace s3m;

namespace {

struct Assoc {
  double t;
  std::string rgb, depth;
};

std::vector<Assoc> read_associations(const std::string& dir) {
  std::ifstream f(dir + "/associations.txt");
  if (!f) throw Error("cannot open " + dir + "/associations.txt");
  std::vector<Assoc> out;
  std::string line;
  while (std::getline(f, line)) {
    if (line.empty() || line[0] == '#') continue;
    std::istringstream s(line);
    Assoc a;
    double td;
    s >> a.t >> a.rgb >> td >> a.depth;
    out.push_back(a);
  }
  return out;
}

std::map<double, SE3> read_groundtruth(const std::string& path) {
  std::ifstream f(path);
  std::map<double, SE3> out;
  std::string line;
  while (std::getline(f, line)) {
    if (line.empty() || line[0] == '#') continue;
    std::istringstream s(line);
    double t, x, y, z, qx, qy, qz, qw;
    s >> t >> x >> y >> z >> qx >> qy >> qz >> qw;
    out[t] = make_se3(Vec3(x, y, z), Quat(qw, qx, qy, qz));
  }
  return out;
}

// Closest ground-truth pose within 20 ms.
const SE3* find_gt(const std::map<double, SE3>& gt, double t) {
  auto it = gt.lower_bound(t - 0.02);
  if (it == gt.end() || std::abs(it->first - t) > 0.02) return nullptr;
  auto next = std::next(it);
  if (next != gt.end() && std::abs(next->first - t) < std::abs(it->first - t)) it = next;
  return &it->second;
}

// Umeyama SE3 (no scale) aligning est to gt: returns T with gt ~ T * est.
SE3 align(const std::vector<Vec3>& est, const std::vector<Vec3>& gt) {
  Vec3 me = Vec3::Zero(), mg = Vec3::Zero();
  for (std::size_t i = 0; i < est.size(); ++i) me += est[i], mg += gt[i];
  me /= est.size();
  mg /= gt.size();
  Mat3 C = Mat3::Zero();
  for (std::size_t i = 0; i < est.size(); ++i) C += (gt[i] - mg) * (est[i] - me).transpose();
  Eigen::JacobiSVD<Mat3> svd(C, Eigen::ComputeFullU | Eigen::ComputeFullV);
  Mat3 S = Mat3::Identity();
  if ((svd.matrixU() * svd.matrixV().transpose()).determinant() < 0) S(2, 2) = -1;
  const Mat3 R = svd.matrixU() * S * svd.matrixV().transpose();
  return make_se3(R, mg - R * me);
}

double rpe_rmse(const std::vector<SE3>& est, const std::vector<SE3>& gt, int delta) {
  double s = 0;
  int n = 0;
  for (std::size_t i = 0; i + delta < est.size(); ++i) {
    const SE3 de = est[i].inverse() * est[i + delta], dg = gt[i].inverse() * gt[i + delta];
    s += (dg.inverse() * de).translation().squaredNorm();
    ++n;
  }
  return n ? std::sqrt(s / n) : 0;
}

}  // namespace

int main(int argc, char** argv) {
  std::string dir = std::getenv("S3M_KITCHEN_DIR") ? std::getenv("S3M_KITCHEN_DIR") : "";
  std::string config_path, out_dir;
  bool threaded = false;
  double depth_factor = 0;
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    if (a == "--threaded") threaded = true;
    else if (a == "--config" && i + 1 < argc) config_path = argv[++i];
    else if (a == "--out" && i + 1 < argc) out_dir = argv[++i];
    else if (a == "--depth-factor" && i + 1 < argc) depth_factor = std::atof(argv[++i]);
    else dir = a;
  }
  if (dir.empty()) {
    std::fprintf(stderr, "usage: bench_slam_kitchen DATASET_DIR [--threaded] [--config F] [--out DIR]\n");
    return 2;
  }
  try {
    const YAML::Node cy = load_yaml_file(dir + "/camera.yaml");
    PinholeCamera cam;
    cam.fx = cy["fx"].as<double>();
    cam.fy = cy["fy"].as<double>();
    cam.cx = cy["cx"].as<double>();
    cam.cy = cy["cy"].as<double>();
    cam.width = cy["width"].as<int>();
    cam.height = cy["height"].as<int>();
    cam.depth_factor = depth_factor > 0 ? depth_factor : cy["depth_factor"].as<double>();
    for (int k = 0; k < 5; ++k) cam.dist[k] = cy[std::vector<std::string>{"k1", "k2", "p1", "p2", "k3"}[k]].as<double>(0.0);
    slam::SlamConfig cfg = config_path.empty() ? slam::SlamConfig{} : slam::load_slam_config(config_path);
    if (threaded) cfg.threaded = true;
    const auto frames = read_associations(dir);
    const auto gt = read_groundtruth(dir + "/groundtruth.txt");
    slam::System slam(cam, cfg);
    std::vector<double> track_ms, total_ms, cpu_ms;
    int lost = 0, kfs = 0;
    Stopwatch wall;
    for (std::size_t i = 0; i < frames.size(); ++i) {
      RgbdFrame f;
      f.index = static_cast<int>(i);
      f.t_s = frames[i].t;
      f.rgb = cv::imread(dir + "/" + frames[i].rgb, cv::IMREAD_COLOR);
      cv::Mat d16 = cv::imread(dir + "/" + frames[i].depth, cv::IMREAD_UNCHANGED);
      if (f.rgb.empty() || d16.empty()) throw Error("cannot read frame " + std::to_string(i));
      d16.convertTo(f.depth_m, CV_32F, 1.0 / cam.depth_factor);
      const auto r = slam.track(f);
      track_ms.push_back(r.track_ms);
      cpu_ms.push_back(r.track_cpu_ms);
      total_ms.push_back(r.track_ms + r.mapping_ms);
      lost += r.state != slam::TrackState::kOk;
      kfs += r.keyframe;
      if (i % 100 == 0 || std::getenv("S3M_SLAM_VERBOSE"))
        std::fprintf(stderr, "frame %zu/%zu state %s inliers %d kfs %d\n", i, frames.size(), slam::to_string(r.state),
                     r.n_inliers, kfs);
    }
    slam.finish();
    const double wall_s = wall.elapsed_ms() / 1000;
    // Accuracy.
    const auto traj = slam.camera_trajectory();
    std::vector<Vec3> pe, pg;
    std::vector<SE3> Te, Tg;
    for (const auto& p : traj)
      if (const SE3* g = find_gt(gt, p.t_s)) {
        pe.push_back(p.T_w_x.translation());
        pg.push_back(g->translation());
        Te.push_back(p.T_w_x);
        Tg.push_back(*g);
      }
    const SE3 A = align(pe, pg);
    double se = 0;
    for (std::size_t i = 0; i < pe.size(); ++i) se += (A * pe[i] - pg[i]).squaredNorm();
    const double ate = std::sqrt(se / std::max<std::size_t>(1, pe.size()));
    const auto ts = timing_stats(track_ms), tt = timing_stats(total_ms), tc = timing_stats(cpu_ms);
    std::printf("dataset %s\nframes %zu tracked %zu lost %d keyframes_inserted %d keyframes_final %d points %d mode %s\n",
                dir.c_str(), frames.size(), traj.size(), lost, kfs, slam.map().n_keyframes(), slam.map().n_points(),
                cfg.threaded ? "threaded" : "single-thread");
    std::printf("ATE_rmse_m %.4f  RPE_1frame_rmse_m %.4f  RPE_1s_rmse_m %.4f\n", ate, rpe_rmse(Te, Tg, 1),
                rpe_rmse(Te, Tg, 30));
    std::printf("tracking_ms mean %.2f p50 %.2f p95 %.2f max %.2f | tracking+inline_mapping_ms mean %.2f | wall %.1f s\n",
                ts.mean_ms, ts.p50_ms, ts.p95_ms, ts.max_ms, tt.mean_ms, wall_s);
    std::printf("tracking_cpu_ms mean %.2f p50 %.2f p95 %.2f (process CPU time; robust to other load)\n", tc.mean_ms,
                tc.p50_ms, tc.p95_ms);
    if (!out_dir.empty()) {
      std::filesystem::create_directories(out_dir);
      slam::write_tum_trajectory(out_dir + "/trajectory_camera.txt", traj);
      slam::write_tum_trajectory(out_dir + "/trajectory_robot.txt", slam.robot_trajectory());
      slam::write_tum_trajectory(out_dir + "/keyframes.txt", slam.keyframe_trajectory());
    }
  } catch (const std::exception& e) {
    std::fprintf(stderr, "error: %s\n", e.what());
    return 1;
  }
  return 0;
}
