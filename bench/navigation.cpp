// Navigation speed on a simulated office (7 x 5 x 2.8 m, loop flight, ground-truth poses) at 5 cm:
//  - BM_EdtUpdatePerKeyframe: dynamicEDT3D's incremental update after one keyframe's rays went into
//    the map (insertion itself is not timed), over the second half of the flight's keyframes;
//  - BM_EdtBuild: the whole field from scratch, what `s3m plan` and `s3m query --clearance` pay per call;
//  - BM_PlanToClass: one `s3m plan --to-class` query on the built field (goal points, grid search,
//    OMPL, simplification) from random free starts (fixed seed) to the classes of the room in turn.
//
//   ./build/bench/bench_navigation --benchmark_counters_tabular=true
#include <memory>
#include <random>

#include <benchmark/benchmark.h>

#include "s3m/core/error.hpp"
#include "s3m/navigation/goals.hpp"
#include "s3m/navigation/planner.hpp"
#include "s3m/sim/gt_voxels.hpp"
#include "s3m/sim/simulate.hpp"

using namespace s3m;

namespace {

constexpr double kRes = 0.05;
constexpr int kKeyframeStep = 10;

struct Flight {
  std::vector<octomap::Pointcloud> clouds;  // per keyframe, world frame [m]
  std::vector<octomap::point3d> origins;
  io::GtVoxelMap gt;
};

const Flight& flight() {
  static const Flight f = [] {
    sim::SimConfig cfg;
    cfg.scene = "office";
    cfg.seed = 3;
    cfg.trajectory.type = "loop";
    cfg.trajectory.frames = 300;
    const sim::Simulation sim(cfg);
    Flight out;
    const auto& cam = sim.camera();
    for (std::size_t i = 0; i < sim.size(); i += kKeyframeStep) {
      const RgbdFrame frame = sim.frame(i);
      const SE3 T_w_c = sim.T_w_c(i);
      octomap::Pointcloud cloud;
      for (int v = 0; v < frame.depth_m.rows; v += 2)
        for (int u = 0; u < frame.depth_m.cols; u += 2) {
          const float z = frame.depth_m.at<float>(v, u);
          if (!(z > 0.3f && z < 4.0f)) continue;
          const Eigen::Vector3d p =
              T_w_c * Eigen::Vector3d((u - cam.cx) * z / cam.fx, (v - cam.cy) * z / cam.fy, z);
          cloud.push_back(float(p.x()), float(p.y()), float(p.z()));
        }
      out.clouds.push_back(std::move(cloud));
      const Eigen::Vector3d o = T_w_c.translation();
      out.origins.emplace_back(float(o.x()), float(o.y()), float(o.z()));
    }
    out.gt = sim::voxelize_scene(sim.scene(), kRes);
    return out;
  }();
  return f;
}

void insert(mapping::SemanticOcTree& tree, std::size_t k) {
  tree.insertPointCloud(flight().clouds[k], flight().origins[k], 5.0, false, true);
}

// The whole flight in a map, occupied voxels labelled with the ground truth's class.
mapping::SemanticOcTree& full_map() {
  static mapping::SemanticOcTree* tree = [] {
    auto* t = new mapping::SemanticOcTree(kRes);
    for (std::size_t k = 0; k < flight().clouds.size(); ++k) insert(*t, k);
    const auto& gt = flight().gt;
    for (std::size_t i = 0; i < gt.centres_w.size(); ++i) {
      const auto& c = gt.centres_w[i];
      const auto* n = t->search(c.x(), c.y(), c.z());
      if (n == nullptr || !t->isNodeOccupied(n)) continue;
      mapping::LabelSet l;
      l.push(gt.labels[i], 0.9f);
      t->integrateObservation(t->coordToKey(c.x(), c.y(), c.z()), l, {128, 128, 128});
    }
    return t;
  }();
  return *tree;
}

void BM_EdtUpdatePerKeyframe(benchmark::State& state) {
  const std::size_t n = flight().clouds.size(), first = n / 2;
  mapping::SemanticOcTree tree(kRes);
  for (std::size_t k = 0; k < first; ++k) insert(tree, k);
  navigation::DistanceField field(tree);
  std::size_t k = first, changed = 0;
  for (auto _ : state) {
    state.PauseTiming();
    insert(tree, k++);
    changed += tree.numChangesDetected();
    state.ResumeTiming();
    field.update();
  }
  state.counters["changed_voxels"] = benchmark::Counter(double(changed) / double(k - first));
  state.counters["keyframes"] = double(k - first);
}
BENCHMARK(BM_EdtUpdatePerKeyframe)->Iterations(15)->Unit(benchmark::kMillisecond)->UseRealTime();

void BM_EdtBuild(benchmark::State& state) {
  auto& tree = full_map();
  for (auto _ : state) {
    navigation::DistanceField field(tree);
    benchmark::DoNotOptimize(field.clearance(Eigen::Vector3d::Zero()));
  }
  double x0, y0, z0, x1, y1, z1;
  tree.getMetricMin(x0, y0, z0);
  tree.getMetricMax(x1, y1, z1);
  state.counters["box_m3"] = (x1 - x0) * (y1 - y0) * (z1 - z0);
}
BENCHMARK(BM_EdtBuild)->Iterations(3)->Unit(benchmark::kMillisecond)->UseRealTime();

void BM_PlanToClass(benchmark::State& state) {
  auto& tree = full_map();
  const navigation::DistanceField field(tree);
  navigation::PlannerConfig pc;
  navigation::ClassGoalConfig gc;
  gc.clearance_m = navigation::required_clearance(field, pc);
  std::vector<ClassId> classes;
  for (const ClassId c :
       {cls::kSofa, cls::kTable, cls::kChair, cls::kCabinet, cls::kShelf, cls::kPlant, cls::kPerson})
    if (!mapping::object_instances(tree, c, gc.min_voxels).empty()) classes.push_back(c);
  std::mt19937 rng(1);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  std::size_t i = 0, failed = 0;
  double length = 0.0;
  for (auto _ : state) {
    state.PauseTiming();
    Eigen::Vector3d s;
    do
      s = field.min_w() +
          (field.max_w() - field.min_w()).cwiseProduct(Eigen::Vector3d(u(rng), u(rng), u(rng)));
    while (field.clearance(s) < gc.clearance_m);
    state.ResumeTiming();
    try {
      const auto goal = navigation::class_goal(field, classes[i++ % classes.size()], s, gc);
      length += navigation::plan_path(field, s, goal.goals_w, pc).length_m;
    } catch (const Error&) {
      ++failed;
    }
  }
  state.counters["failed"] = double(failed);
  state.counters["mean_length_m"] = length / double(std::max<std::size_t>(1, i - failed));
}
BENCHMARK(BM_PlanToClass)->Iterations(30)->Unit(benchmark::kMillisecond)->UseRealTime();

}  // namespace

BENCHMARK_MAIN();
