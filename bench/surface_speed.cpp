// Time per relaxed edge of Dijkstra and STVD(k) on surfaces: an icosphere
// (isotropic and curvature metric) and a jittered quad plane. Counters as in
// propagation_speed: time_per_edge, relaxed_edges. Run with
// --benchmark_counters_tabular=true.
#include <benchmark/benchmark.h>

#include <map>
#include <memory>

#include "../tests/surface/surface_meshes.hpp"
#include "stvd/propagation/propagation.hpp"
#include "stvd/surface/surface_domain.hpp"
#include "stvd/surface/surface_metrics.hpp"
#include "stvd/surface/surface_propagation.hpp"

namespace {

using namespace stvd;

struct SurfaceScene {
  SurfaceDomain domain;
  RiemannianMetric metric;
};

// Scene 0: icosphere (6 subdivisions, 40,962 vertices), isotropic.
// Scene 1: a quad prism (256 x 160 quads) under the curvature metric,
//          gamma 10.
// Scene 2: jittered quad plane 200 x 200, isotropic.
const SurfaceScene& scene(int which) {
  static std::map<int, std::unique_ptr<SurfaceScene>> scenes;
  auto& s = scenes[which];
  if (s) return *s;
  test::GeneratedSurface g = which == 0   ? test::icosphere(6, 1.0)
                             : which == 1 ? test::prismMesh(256, 160, 1.0, 0.02, true, 1)
                                          : test::planeMesh(200, 200, 1.0, 1.0, 0.5, 0.5, true, 1);
  SurfaceDomain d(g.points, g.faces);
  RiemannianMetric m = which == 1 ? curvatureMetric(d, 10.0) : isotropicSurfaceMetric(d);
  s = std::make_unique<SurfaceScene>(SurfaceScene{std::move(d), std::move(m)});
  return *s;
}

void surfacePropagation(benchmark::State& state) {
  const int which = static_cast<int>(state.range(0));
  const int k = static_cast<int>(state.range(1));  // 0: Dijkstra
  const SurfaceScene& s = scene(which);
  PropagationOptions options;
  options.method = k == 0 ? Method::Dijkstra : Method::ShortTermVectorDijkstra;
  options.k = k == 0 ? 1 : k;
  std::uint64_t edges = 0;
  for (auto _ : state) {
    PropagationResult r = propagate(s.domain, s.metric, {0}, options);
    edges = r.relaxedEdges;
    benchmark::DoNotOptimize(r.distance.data());
  }
  state.counters["relaxed_edges"] = double(edges);
  state.counters["time_per_edge"] = benchmark::Counter(
      double(edges), benchmark::Counter::kIsIterationInvariantRate | benchmark::Counter::kInvert);
  static const char* names[] = {"icosphere isotropic", "quad prism curvature g10",
                                "quad plane isotropic"};
  state.SetLabel(std::string(names[which]) + (k == 0 ? ", Dijkstra" : ", STVD k=" + std::to_string(k)));
}

BENCHMARK(surfacePropagation)
    ->ArgNames({"scene", "k"})
    ->ArgsProduct({{0, 1, 2}, {0, 5, 8}})
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime();

}  // namespace

BENCHMARK_MAIN();
