// Time per relaxed edge of Dijkstra and STVD(k) on n^3 grids with the
// 26-neighbourhood and the (spatially varying) pull-back metric, gamma 20.
// Counters: time_per_edge (wall seconds per relaxed edge), relaxed_edges and
// state_bytes_per_voxel. Run with --benchmark_counters_tabular=true.
#include <benchmark/benchmark.h>

#include <map>
#include <memory>

#include "bench_scenes.hpp"

namespace {

using namespace stvd;

const bench::Scene& scene(int n) {
  static std::map<int, std::unique_ptr<bench::Scene>> scenes;
  auto& s = scenes[n];
  // Exact distances are not needed here: stride n skips their evaluation
  // except at the origin voxel.
  if (!s) s = std::make_unique<bench::Scene>(bench::pullbackScene(n, 20.0, Stencil::full26(), n));
  return *s;
}

void propagation(benchmark::State& state) {
  const int n = static_cast<int>(state.range(0));
  const int k = static_cast<int>(state.range(1));  // 0: Dijkstra
  const bench::Scene& s = scene(n);
  PropagationOptions options;
  options.method = k == 0 ? Method::Dijkstra : Method::ShortTermVectorDijkstra;
  options.k = k == 0 ? 1 : k;
  std::uint64_t edges = 0, bytes = 0;
  for (auto _ : state) {
    PropagationResult r = propagate(s.domain, s.metric, {s.source}, options);
    edges = r.relaxedEdges;
    bytes = r.peakStateBytes;
    benchmark::DoNotOptimize(r.distance.data());
  }
  state.counters["relaxed_edges"] = double(edges);
  // Inverted rate: wall seconds per relaxed edge (printed with an SI prefix, n = 1e-9).
  state.counters["time_per_edge"] = benchmark::Counter(
      double(edges), benchmark::Counter::kIsIterationInvariantRate | benchmark::Counter::kInvert);
  state.counters["state_bytes_per_voxel"] = double(bytes) / s.domain.vertexCount();
  state.SetLabel(k == 0 ? "Dijkstra" : "STVD k=" + std::to_string(k));
}

BENCHMARK(propagation)
    ->ArgNames({"n", "k"})
    ->ArgsProduct({{32, 64, 128}, {0, 2, 3, 4, 5, 6, 8, 10, 12, 16}})
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime();

// The same with a progress callback and an interrupter, as the tool, the
// Python package and the ITK filter run it: reports paced in time (the loop
// reads the clock every 1024 vertices). Compare with `propagation` above:
// the pacing must cost nothing measurable.
void propagation_reporting(benchmark::State& state) {
  const int n = static_cast<int>(state.range(0));
  const int k = static_cast<int>(state.range(1));  // 0: Dijkstra
  const bench::Scene& s = scene(n);
  PropagationOptions options;
  options.method = k == 0 ? Method::Dijkstra : Method::ShortTermVectorDijkstra;
  options.k = k == 0 ? 1 : k;
  std::uint64_t reports = 0;
  options.progress = [&reports](const PropagationProgress&) {
    ++reports;
    return true;
  };
  Interrupter interrupter;
  options.interrupter = &interrupter;
  std::uint64_t edges = 0;
  for (auto _ : state) {
    PropagationResult r = propagate(s.domain, s.metric, {s.source}, options);
    edges = r.relaxedEdges;
    benchmark::DoNotOptimize(r.distance.data());
  }
  state.counters["time_per_edge"] = benchmark::Counter(
      double(edges), benchmark::Counter::kIsIterationInvariantRate | benchmark::Counter::kInvert);
  state.counters["reports_per_run"] = double(reports) / double(state.iterations());
  state.SetLabel(k == 0 ? "Dijkstra" : "STVD k=" + std::to_string(k));
}

BENCHMARK(propagation_reporting)
    ->ArgNames({"n", "k"})
    ->ArgsProduct({{128}, {0, 6}})
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime();

}  // namespace

BENCHMARK_MAIN();
