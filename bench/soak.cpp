// Soak: a long simulator flight through the full pipeline (SLAM, oracle segmentation, semantic
// map), flying the same lap over and over, with memory sampled over time. Memory must stay bounded:
// the pipeline's kept clouds (KeyframeStore budget), SLAM's map (keyframe culling) and the octree
// (the area is fixed) must stop growing once the area has been seen.
//
//   build/bench/bench_soak [--frames 5000] [--lap 300] [--trajectory figure8] [--scene office]
//                          [--every 50] [--config config/sim.yaml] [--csv soak.csv] [--threaded]
//
// Frames are rendered on the fly (nothing on disk); frame i is lap frame i % lap with index and
// timestamp continuing, so every lap re-flies exactly the same path. Deterministic mode (one
// thread) so that the map and SLAM can be inspected between frames. The CSV has one row per sample:
// frame, rss_mb, cpu_s, kept_clouds, kept_mb, slam_keyframes, map_leaves, map_mb, tracked, state.
// --threaded runs the pipeline's threaded mode (the stages on their own threads, as `s3m run`):
// the stages' structures belong to other threads then, so a sample has only frame, rss_mb and
// cpu_s (the other columns empty) and the summary's structure sizes are read after finish().
// Prints a JSON summary on stdout. Not a ctest test: it takes minutes.
#include <sys/resource.h>

#include <cstdio>
#include <ctime>
#include <fstream>
#include <iostream>
#include <string>

#include <nlohmann/json.hpp>

#include "s3m/core/error.hpp"
#include "s3m/core/frame_state.hpp"
#include "s3m/core/shipped_files.hpp"
#include "s3m/mapping/metrics.hpp"
#include "s3m/pipeline/factories.hpp"
#include "s3m/pipeline/pipeline.hpp"
#include "s3m/semantics/oracle_segmenter.hpp"
#include "s3m/sim/simulate.hpp"

namespace {
using namespace s3m;

struct Options {
  long frames = 5000;
  int lap = 300;
  int every = 50;
  std::string trajectory = "figure8", scene = "office", config, csv = "soak.csv";
  bool threaded = false;
};

Options parse(int argc, char** argv) {
  Options o;
  o.config = s3m::shipped_file("config/sim.yaml");
  for (int i = 1; i < argc; ++i) {
    const std::string k = argv[i];
    if (k == "--threaded") {
      o.threaded = true;
      continue;
    }
    if (i + 1 >= argc) throw Error("bench_soak: " + k + " needs a value");
    const std::string v = argv[++i];
    if (k == "--frames")
      o.frames = std::stol(v);
    else if (k == "--lap")
      o.lap = std::stoi(v);
    else if (k == "--every")
      o.every = std::stoi(v);
    else if (k == "--trajectory")
      o.trajectory = v;
    else if (k == "--scene")
      o.scene = v;
    else if (k == "--config")
      o.config = v;
    else if (k == "--csv")
      o.csv = v;
    else
      throw Error("bench_soak: unknown option " + k);
  }
  require(o.frames > 0 && o.lap > 1 && o.every > 0, "bench_soak: --frames, --lap, --every must be > 0");
  return o;
}

double rss_mb() {
  std::ifstream f("/proc/self/status");
  std::string key;
  while (f >> key) {
    if (key == "VmRSS:") {
      double kb = 0;
      f >> kb;
      return kb / 1024.0;
    }
    f.ignore(1 << 12, '\n');
  }
  return 0.0;
}

double cpu_s() {
  rusage u{};
  getrusage(RUSAGE_SELF, &u);
  return u.ru_utime.tv_sec + u.ru_stime.tv_sec + (u.ru_utime.tv_usec + u.ru_stime.tv_usec) / 1e6;
}

int run(const Options& o) {
  sim::SimConfig sc;
  sc.scene = o.scene;
  sc.trajectory.type = o.trajectory;
  sc.trajectory.frames = o.lap;
  const sim::Simulation sim(sc);
  pipeline::PipelineConfig config = pipeline::load_pipeline_config(o.config);
  config.threads.deterministic = !o.threaded;
  auto poses = pipeline::make_slam_poses(sim.camera(), config);
  auto seg = std::make_unique<semantics::OracleSegmenter>(config.segmenter.oracle, config.segmenter.top_k);
  auto map = std::make_unique<pipeline::MapIntegrator>(config.map);
  pipeline::Pipeline p(config, sim.camera(), std::move(poses), std::move(seg), std::move(map));

  std::ofstream csv(o.csv);
  require(csv.good(), "bench_soak: cannot write " + o.csv);
  csv << "frame,rss_mb,cpu_s,kept_clouds,kept_mb,slam_keyframes,map_leaves,map_mb,tracked,state\n";
  const double dt_s = 1.0 / sc.trajectory.fps;
  for (long i = 0; i < o.frames; ++i) {
    RgbdFrame f = sim.frame(static_cast<std::size_t>(i % o.lap));
    f.index = static_cast<int>(i);
    f.t_s = sc.trajectory.start_time_s + static_cast<double>(i) * dt_s;
    p.process(std::move(f));
    if ((i + 1) % o.every != 0 && i + 1 != o.frames) continue;
    csv << i + 1 << ',' << rss_mb() << ',' << cpu_s() << ',';
    if (o.threaded) {  // the stages' structures belong to other threads: leave them out
      csv << ",,,,,,\n";
    } else {
      const auto& tree = p.map()->tree();
      csv << p.keyframe_store().size() << ',' << p.keyframe_store().bytes() / 1e6 << ','
          << p.poses().keyframe_poses().size() << ',' << tree.getNumLeafNodes() << ','
          << tree.memoryUsage() / 1e6 << ',' << p.counters().tracked << ','
          << (p.last_state() ? to_string(*p.last_state()) : std::string()) << '\n';
    }
    csv.flush();
    std::fprintf(stderr, "\rsoak: %ld/%ld frames, rss %.0f MB", i + 1, o.frames, rss_mb());
  }
  p.finish();
  std::fprintf(stderr, "\n");
  nlohmann::json s = {{"frames", o.frames},
                      {"threaded", o.threaded},
                      {"lap", o.lap},
                      {"trajectory", o.trajectory},
                      {"scene", o.scene},
                      {"tracked", p.counters().tracked},
                      {"keyframes_created", p.counters().keyframes},
                      {"integrated", p.counters().integrated},
                      {"rebuilds", p.counters().rebuilds},
                      {"kept_clouds", p.keyframe_store().size()},
                      {"kept_mb", p.keyframe_store().bytes() / 1e6},
                      {"slam_keyframes", p.poses().keyframe_poses().size()},
                      {"map_leaves", p.map()->tree().getNumLeafNodes()},
                      {"rss_mb_end", rss_mb()},
                      {"cpu_s", cpu_s()},
                      {"csv", o.csv}};
  std::cout << s.dump(2) << std::endl;
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  try {
    return run(parse(argc, argv));
  } catch (const std::exception& e) {
    std::fprintf(stderr, "bench_soak: error: %s\n", e.what());
    return 1;
  }
}
