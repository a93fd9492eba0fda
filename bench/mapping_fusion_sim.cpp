// Semantic fusion on simulated frames with known ground truth: for each fusion policy, the fused
// map's mIoU / occupancy precision-recall against the simulator's ground-truth voxels, versus
// single-frame maps; and insertion time ours vs stock OctoMap on the same simulated clouds.
//
//   [S3M_SIM_FRAMES=60] ./build/bench/bench_mapping_fusion_sim --benchmark_counters_tabular=true
//
// Scene "office", uav_sweep trajectory, seed 7; labels from the noisy oracle segmenter (k = 3,
// confusions, drops and boundary flips, calibrated confidences). Needs no data files.
#include <cstdlib>
#include <set>

#include <benchmark/benchmark.h>
#include <octomap/OcTree.h>

#include "occupied_keys.hpp"
#include "s3m/core/timing.hpp"
#include "s3m/mapping/insert.hpp"
#include "s3m/mapping/metrics.hpp"
#include "s3m/semantics/oracle_segmenter.hpp"
#include "s3m/sim/gt_voxels.hpp"
#include "s3m/sim/simulate.hpp"

using namespace s3m;
using namespace s3m::mapping;
using s3m::bench::occupied_keys;

namespace {

constexpr double kRes = 0.05;

struct SimData {
  std::vector<LabeledCloud> clouds;
  io::GtVoxelMap gt;
};

LabeledCloud to_cloud(const RgbdFrame& f, const semantics::LabelMap& lm, const PinholeCamera& cam, const SE3& T_w_c) {
  LabeledCloud c;
  c.k = lm.k();
  c.origin = T_w_c.translation().cast<float>();
  const Eigen::Isometry3f T = T_w_c.cast<float>();
  for (int v = 0; v < f.depth_m.rows; ++v)
    for (int u = 0; u < f.depth_m.cols; ++u) {
      const float z = f.depth_m.at<float>(v, u);
      if (!(z > 0.0f)) continue;
      const cv::Vec3b bgr = f.rgb.at<cv::Vec3b>(v, u);
      ClassId ids[kMaxLabels];
      float probs[kMaxLabels];
      for (int j = 0; j < c.k; ++j) ids[j] = lm.id(v, u, j), probs[j] = lm.prob(v, u, j);
      c.push_back(T * cam.backproject(u, v, z).cast<float>(), bgr[2], bgr[1], bgr[0], ids, probs);
    }
  return c;
}

const SimData& data() {
  static const SimData d = [] {
    SimData out;
    sim::SimConfig cfg;
    const char* n = std::getenv("S3M_SIM_FRAMES");
    cfg.trajectory.frames = n ? std::max(10, std::atoi(n)) : 60;
    const sim::Simulation simulation(cfg);
    semantics::OracleNoiseConfig noise;
    noise.enabled = true;
    noise.seed = 1;
    semantics::OracleSegmenter oracle(noise, 3);
    for (std::size_t i = 0; i < simulation.size(); ++i) {
      const RgbdFrame f = simulation.frame(i);
      out.clouds.push_back(to_cloud(f, oracle.segment(f), simulation.camera(), simulation.trajectory().samples[i].T_w_c));
    }
    out.gt = sim::voxelize_scene(simulation.scene(), kRes);
    std::fprintf(stderr, "mapping_fusion_sim: %zu frames, %zu points in frame 0, %zu GT voxels\n", out.clouds.size(),
                 out.clouds[0].size(), out.gt.centres_w.size());
    return out;
  }();
  return d;
}

void report(benchmark::State& state, const MapEvaluation& ev) {
  state.counters["miou"] = ev.miou;
  state.counters["miou_observed"] = ev.miou_observed;
  state.counters["label_acc"] = ev.label_accuracy;
  state.counters["precision"] = ev.precision;
  state.counters["recall"] = ev.recall;
}

void BM_FusedMap(benchmark::State& state) {
  FusionConfig fusion;
  fusion.policy = FusionPolicy(state.range(0));
  MapEvaluation ev;
  for (auto _ : state) {
    SemanticOcTree tree(kRes);
    tree.setFusionConfig(fusion);
    Inserter inserter;
    for (const auto& c : data().clouds) inserter.insert(c, tree);
    ev = evaluate_map(tree, data().gt);
  }
  report(state, ev);
  state.SetLabel(to_string(fusion.policy));
}

// Mean over frames of a map built from that frame alone (labels not fused across views).
void BM_SingleFrameMaps(benchmark::State& state) {
  MapEvaluation mean;
  for (auto _ : state) {
    mean = MapEvaluation{};
    const auto& clouds = data().clouds;
    for (const auto& c : clouds) {
      SemanticOcTree tree(kRes);
      Inserter().insert(c, tree);
      const MapEvaluation ev = evaluate_map(tree, data().gt);
      mean.miou += ev.miou / double(clouds.size());
      mean.miou_observed += ev.miou_observed / double(clouds.size());
      mean.label_accuracy += ev.label_accuracy / double(clouds.size());
      mean.precision += ev.precision / double(clouds.size());
      mean.recall += ev.recall / double(clouds.size());
    }
  }
  report(state, mean);
}

// Insertion time on simulated clouds, ours (stock-equivalent filters) vs stock, and agreement.
void BM_SimInsertOursVsStock(benchmark::State& state) {
  const double res = state.range(0) / 100.0;
  InsertConfig cfg;
  cfg.radius_min_neighbors = 0;
  double ours_ms = 1e300, stock_ms = 1e300;
  std::unique_ptr<SemanticOcTree> ours;
  std::unique_ptr<octomap::OcTree> stock;
  for (auto _ : state) {
    Stopwatch sw;
    ours = std::make_unique<SemanticOcTree>(res);
    Inserter inserter(cfg);
    for (const auto& c : data().clouds) inserter.insert(c, *ours);
    ours_ms = std::min(ours_ms, sw.elapsed_ms());
    sw.reset();
    stock = std::make_unique<octomap::OcTree>(res);
    for (const auto& c : data().clouds) {
      octomap::Pointcloud pc;
      for (const auto& p : c.points) pc.push_back(p.x(), p.y(), p.z());
      stock->insertPointCloud(pc, octomap::point3d(c.origin.x(), c.origin.y(), c.origin.z()), 4.0, false, true);
    }
    stock_ms = std::min(stock_ms, sw.elapsed_ms());
  }
  const double n = double(data().clouds.size());
  const auto a = occupied_keys(*ours), b = occupied_keys(*stock);
  std::size_t common = 0;
  for (auto k : a) common += b.count(k);
  state.counters["ours_ms_per_frame"] = ours_ms / n;
  state.counters["stock_ms_per_frame"] = stock_ms / n;
  state.counters["speedup"] = stock_ms / ours_ms;
  state.counters["occupied_agreement_pct"] = 100.0 * double(common) / double(std::max(a.size(), b.size()));
}

}  // namespace

BENCHMARK(BM_FusedMap)->Arg(0)->Arg(1)->Arg(2)->Unit(benchmark::kMillisecond)->Iterations(1);
BENCHMARK(BM_SingleFrameMaps)->Unit(benchmark::kMillisecond)->Iterations(1);
BENCHMARK(BM_SimInsertOursVsStock)->Arg(5)->Arg(2)->Unit(benchmark::kMillisecond)->Iterations(1)->UseRealTime();
BENCHMARK_MAIN();
