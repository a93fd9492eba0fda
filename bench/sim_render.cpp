// Simulator speed: one 640x480 RGB-D-label frame (ideal and with the sensor model) on one core
// and on all cores, and a full 300-frame sequence written to disk.
//   build/bench/bench_sim_render [--benchmark_filter=...]
//   S3M_SIM_BENCH_OUT=/tmp/simbench  (where the sequence goes; default: a temp directory)
#include <cstdlib>
#include <filesystem>

#include <benchmark/benchmark.h>
#include <tbb/global_control.h>

#include "s3m/sim/simulate.hpp"

namespace {

using namespace s3m;

const sim::Simulation& office() {
  static const sim::Simulation s{sim::SimConfig{}};
  return s;
}

void BM_RenderIdeal(benchmark::State& state) {
  tbb::global_control threads(tbb::global_control::max_allowed_parallelism, state.range(0));
  const auto& sim = office();
  std::size_t i = 0;
  for (auto _ : state) {
    benchmark::DoNotOptimize(sim.renderer().render_ideal(sim.trajectory().samples[i].T_w_c));
    i = (i + 7) % sim.size();
  }
  state.counters["fps"] = benchmark::Counter(static_cast<double>(state.iterations()), benchmark::Counter::kIsRate);
}
BENCHMARK(BM_RenderIdeal)->Arg(1)->Arg(2)->Unit(benchmark::kMillisecond)->UseRealTime();

void BM_SensorFrame(benchmark::State& state) {
  tbb::global_control threads(tbb::global_control::max_allowed_parallelism, state.range(0));
  const auto& sim = office();
  std::size_t i = 0;
  for (auto _ : state) {
    benchmark::DoNotOptimize(sim.frame(i));
    i = (i + 7) % sim.size();
  }
  state.counters["fps"] = benchmark::Counter(static_cast<double>(state.iterations()), benchmark::Counter::kIsRate);
}
BENCHMARK(BM_SensorFrame)->Arg(1)->Arg(2)->Unit(benchmark::kMillisecond)->UseRealTime();

void BM_Sequence300(benchmark::State& state) {
  const char* env = std::getenv("S3M_SIM_BENCH_OUT");
  const std::string out = env ? env : (std::filesystem::temp_directory_path() / "s3m_sim_bench").string();
  for (auto _ : state) {
    std::filesystem::remove_all(out);
    const sim::SimSummary s = sim::simulate_sequence(sim::SimConfig{}, out);
    state.counters["render_ms_per_frame"] = s.render_ms_mean;
    state.counters["seconds"] = s.seconds;
  }
  if (!env) std::filesystem::remove_all(out);
}
BENCHMARK(BM_Sequence300)->Iterations(1)->Unit(benchmark::kSecond)->UseRealTime();

}  // namespace

BENCHMARK_MAIN();
