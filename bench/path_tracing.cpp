// Time to trace geodesic paths (stvd/voxel_grid/path_tracing.hpp) once the distance is
// propagated, against the propagation itself, on the n^3 pull-back scene
// (gamma 20, 26-neighbourhood) with the propagation defaults of the library
// and the tool (STVD, k = 8, segment measure). Paths run from the source to the 8
// voxels halfway to the grid's corners. Counters: time_per_path and
// time_per_step (wall seconds), steps per path. Run with
// --benchmark_counters_tabular=true.
#include <benchmark/benchmark.h>

#include <map>
#include <memory>

#include "bench_scenes.hpp"
#include "stvd/voxel_grid/path_tracing.hpp"

namespace {

using namespace stvd;

PropagationOptions toolDefaults() { return PropagationOptions{}; }

struct Traced {
  bench::Scene scene;
  PropagationResult result;
  std::vector<VertexId> targets;
};

const Traced& traced(int n) {
  static std::map<int, std::unique_ptr<Traced>> cache;
  auto& t = cache[n];
  if (!t) {
    t = std::make_unique<Traced>(Traced{bench::pullbackScene(n, 20.0, Stencil::full26(), n), {}, {}});
    t->result = propagate(t->scene.domain, t->scene.metric, {t->scene.source}, toolDefaults());
    const VoxelIndex s = t->scene.domain.indexOf(t->scene.source);
    for (int corner = 0; corner < 8; ++corner) {
      const int i = (corner & 1) ? (s.i + n - 1) / 2 : s.i / 2, j = (corner & 2) ? (s.j + n - 1) / 2 : s.j / 2,
                k = (corner & 4) ? (s.k + n - 1) / 2 : s.k / 2;
      t->targets.push_back(t->scene.domain.vertexAt(i, j, k));
    }
  }
  return *t;
}

void tracing(benchmark::State& state) {
  const Traced& t = traced(static_cast<int>(state.range(0)));
  std::size_t steps = 0;
  for (auto _ : state) {
    steps = 0;
    for (VertexId target : t.targets) {
      const TracedPath path = traceGeodesicPath(t.scene.domain, t.scene.metric, t.result, target);
      steps += path.gradientSteps;
      benchmark::DoNotOptimize(path.points.data());
    }
  }
  state.counters["time_per_path"] = benchmark::Counter(
      double(t.targets.size()), benchmark::Counter::kIsIterationInvariantRate | benchmark::Counter::kInvert);
  state.counters["time_per_step"] =
      benchmark::Counter(double(steps), benchmark::Counter::kIsIterationInvariantRate | benchmark::Counter::kInvert);
  state.counters["steps_per_path"] = double(steps) / t.targets.size();
}

void propagationForComparison(benchmark::State& state) {
  const Traced& t = traced(static_cast<int>(state.range(0)));
  for (auto _ : state) {
    PropagationResult r = propagate(t.scene.domain, t.scene.metric, {t.scene.source}, toolDefaults());
    benchmark::DoNotOptimize(r.distance.data());
  }
}

BENCHMARK(tracing)->ArgName("n")->Arg(64)->Arg(128)->Unit(benchmark::kMillisecond)->UseRealTime();
BENCHMARK(propagationForComparison)->ArgName("n")->Arg(64)->Arg(128)->Unit(benchmark::kMillisecond)->UseRealTime();

}  // namespace

BENCHMARK_MAIN();
