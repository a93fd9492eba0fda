// RGB-D SLAM on a TUM-layout sequence (default: the 7-Scenes redkitchen 500-frame excerpt).
// Prints ATE RMSE (SE3 Umeyama alignment), RPE (1 frame and 1 s), tracking ms/frame, lost frames.
//   bench_slam_kitchen [DATASET_DIR] [--threaded] [--config FILE] [--camera FILE] [--out DIR]
//                      [--frame camera|robot] [--realtime]
// --frame robot evaluates T_w_r = T_w_c * T_c_r (slam.T_c_r of the config) instead of T_w_c: for
// ground truth of another rigidly attached sensor (7-Scenes: the depth camera).
// --realtime hands each frame to SLAM no earlier than its timestamp (relative to the first), as a
// live camera would; without it frames go in as fast as tracking takes them, which in threaded
// mode leaves local mapping further behind than it would ever be on a 30 Hz camera.
// DATASET_DIR defaults to $S3M_KITCHEN_DIR. Frames and ground truth are read with io::TumDataset
// (intrinsics: --camera, a preset name or YAML file, else DATASET_DIR/camera.yaml) and accuracy is
// computed by eval::evaluate_trajectory with s3m eval's defaults, so the ATE printed here is the
// one `s3m eval --gt DATASET_DIR/groundtruth.txt --est OUT/trajectory_camera.txt` reports (with
// --out the evaluation reads the written file back, and OUT/metrics.json is s3m eval's file).
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <string>
#include <thread>
#include <vector>

#include "s3m/core/error.hpp"
#include "s3m/core/timing.hpp"
#include "s3m/eval/report.hpp"
#include "s3m/eval/trajectory_eval.hpp"
#include "s3m/io/trajectory.hpp"
#include "s3m/io/tum_dataset.hpp"
#include "s3m/slam/system.hpp"

using namespace s3m;

namespace {

struct Args {
  std::string dir, config, camera, out;
  bool threaded = false;
  bool robot = false;  // evaluate T_w_r = T_w_c * T_c_r instead of the camera trajectory
  bool realtime = false;
};

Args parse_args(int argc, char** argv) {
  Args a;
  if (const char* env = std::getenv("S3M_KITCHEN_DIR")) a.dir = env;
  for (int i = 1; i < argc; ++i) {
    const std::string s = argv[i];
    const bool has_value = i + 1 < argc;
    if (s == "--threaded")
      a.threaded = true;
    else if (s == "--realtime")
      a.realtime = true;
    else if (s == "--config" && has_value)
      a.config = argv[++i];
    else if (s == "--camera" && has_value)
      a.camera = argv[++i];
    else if (s == "--out" && has_value)
      a.out = argv[++i];
    else if (s == "--frame" && has_value) {
      const std::string f = argv[++i];
      if (f != "camera" && f != "robot") throw Error("--frame must be camera or robot, not '" + f + "'");
      a.robot = f == "robot";
    } else if (!s.empty() && s[0] == '-')
      throw Error("unknown option '" + s + "'");
    else
      a.dir = s;
  }
  if (a.dir.empty()) throw Error("no dataset directory (argument or $S3M_KITCHEN_DIR)");
  return a;
}

// Every frame SLAM reports, LOST ones included (s3m run leaves those out).
io::Trajectory to_io(const std::vector<slam::FramePose>& frames) { return {frames.begin(), frames.end()}; }

struct RunStats {
  std::vector<double> track_ms, cpu_ms, total_ms;
  int lost = 0, keyframes = 0;
  double wall_s = 0;
};

RunStats run(slam::System& slam, const io::TumDataset& ds, bool realtime) {
  RunStats st;
  Stopwatch wall;
  const auto start = std::chrono::steady_clock::now();
  double t0_s = 0;
  for (std::size_t i = 0; i < ds.size(); ++i) {
    RgbdFrame f = ds.load(i);
    f.index = static_cast<int>(i);
    if (i == 0) t0_s = f.t_s;
    if (realtime)
      std::this_thread::sleep_until(start + std::chrono::duration_cast<std::chrono::steady_clock::duration>(
                                                std::chrono::duration<double>(f.t_s - t0_s)));
    const auto r = slam.track(f);
    st.track_ms.push_back(r.track_ms);
    st.cpu_ms.push_back(r.track_cpu_ms);
    st.total_ms.push_back(r.track_ms + r.mapping_ms);
    st.lost += r.state != FrameState::kOk;
    st.keyframes += r.keyframe;
    if (i % 100 == 0 || std::getenv("S3M_SLAM_VERBOSE"))
      std::fprintf(stderr, "frame %zu/%zu state %s inliers %d kfs %d\n", i, ds.size(), to_string(r.state),
                   r.n_inliers, st.keyframes);
  }
  slam.finish();
  st.wall_s = wall.elapsed_ms() / 1000;
  return st;
}

}  // namespace

int main(int argc, char** argv) {
  try {
    const Args a = parse_args(argc, argv);
    io::TumDatasetOptions dopt;
    dopt.camera = a.camera;
    const auto ds = io::TumDataset::open(a.dir, dopt);
    if (ds.groundtruth().empty()) throw Error(a.dir + ": no groundtruth.txt, nothing to evaluate against");
    slam::SlamConfig cfg = a.config.empty() ? slam::SlamConfig{} : slam::load_slam_config(a.config);
    // The mode is the flag's, not the preset's: pipeline presets (config/kitchen_7scenes.yaml) run
    // local mapping threaded, and the tracking-time target is single-thread.
    cfg.threaded = a.threaded;
    slam::System slam(ds.camera(), cfg);
    const RunStats st = run(slam, ds, a.realtime);

    // Accuracy with the project's evaluation (s3m eval's defaults: se3 alignment, 20 ms window).
    const auto traj = slam.camera_trajectory();
    io::Trajectory est = to_io(a.robot ? slam.robot_trajectory() : traj);
    if (!a.out.empty()) {
      std::filesystem::create_directories(a.out);
      io::write_tum_trajectory(a.out + "/trajectory_camera.txt", to_io(traj));
      io::write_tum_trajectory(a.out + "/trajectory_robot.txt", to_io(slam.robot_trajectory()));
      io::write_tum_trajectory(a.out + "/keyframes.txt", to_io(slam.keyframe_trajectory()));
      // Evaluate exactly what s3m eval would read.
      est = io::read_tum_trajectory(a.out + (a.robot ? "/trajectory_robot.txt" : "/trajectory_camera.txt"));
    }
    eval::EvalOptions eopt;  // RPE over 1 s
    const auto ev = eval::evaluate_trajectory(ds.groundtruth(), est, eopt, "slam");
    eval::EvalOptions fopt = eopt;
    fopt.rpe = {1.0, eval::DeltaUnit::kFrames};
    const auto ev1 = eval::evaluate_trajectory(ds.groundtruth(), est, fopt, "slam");
    eval::EvalOptions sopt = eopt;  // diagnostic: a scale error (wrong focal length or depth factor)
    sopt.align = eval::AlignMode::kSim3;
    const auto evs = eval::evaluate_trajectory(ds.groundtruth(), est, sopt, "slam");
    if (!a.out.empty()) eval::write_metrics_json(a.out + "/metrics.json", {ev}, eopt);

    const auto ts = timing_stats(st.track_ms), tt = timing_stats(st.total_ms), tc = timing_stats(st.cpu_ms);
    std::printf(
        "dataset %s\nframes %zu tracked %zu lost %d keyframes_inserted %d keyframes_final %d points %d "
        "mode %s\n",
        a.dir.c_str(), ds.size(), traj.size(), st.lost, st.keyframes, slam.map().n_keyframes(),
        slam.map().n_points(), cfg.threaded ? "threaded" : "single-thread");
    std::printf("evaluated trajectory: %s\n", a.robot ? "robot (T_w_c * T_c_r)" : "camera");
    std::printf("ATE_rmse_m %.4f  RPE_1frame_rmse_m %.4f  RPE_1s_rmse_m %.4f  (matched %zu)\n",
                ev.ate.stats_m.rmse, ev1.rpe.trans_m.rmse, ev.rpe.trans_m.rmse, ev.matched);
    if (std::isfinite(evs.ate.alignment.scale))
      std::printf("sim3 alignment: scale %.4f ATE_rmse_m %.4f (diagnostic)\n", evs.ate.alignment.scale,
                  evs.ate.stats_m.rmse);
    else  // eval's Sim3 has no scale for an estimate without spread (every pose the same)
      std::printf("sim3 alignment: undefined (the estimated positions have no spread)\n");
    std::printf(
        "tracking_ms mean %.2f p50 %.2f p95 %.2f max %.2f | tracking+inline_mapping_ms mean %.2f | "
        "wall %.1f s\n",
        ts.mean_ms, ts.p50_ms, ts.p95_ms, ts.max_ms, tt.mean_ms, st.wall_s);
    std::printf("tracking_cpu_ms mean %.2f p50 %.2f p95 %.2f (process CPU time; robust to other load)\n",
                tc.mean_ms, tc.p50_ms, tc.p95_ms);
  } catch (const std::exception& e) {
    std::fprintf(stderr,
                 "bench_slam_kitchen: error: %s\n"
                 "usage: bench_slam_kitchen DATASET_DIR [--threaded] [--config F] [--camera F] [--out DIR]"
                 " [--frame camera|robot]\n",
                 e.what());
    return 1;
  }
  return 0;
}
