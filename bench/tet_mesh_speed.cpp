// Time per relaxed edge of Dijkstra and STVD(k) on TetGen quality meshes of
// a box, next to the 128^3 grid with the 26-neighbourhood in the same run,
// and the mean relative error of each tet-mesh run against the exact
// distance. Metrics: constant gamma = 12 along an oblique axis ("constant",
// exact ||x - s||_G), and the curved pull-back of the tests, gamma = 12
// ("curved", exact |phi(x) - phi(s)|; every vertex is counted: on the 55k
// mesh the tests find the straight image segment inside phi(box) for all of
// them).
// Counters: time_per_edge (CPU seconds per relaxed edge: on a machine
// shared with other work, wall time measured up to twice the CPU time and
// varied from run to run), relaxed_edges, mean_error, max_error, vertices,
// edges_per_vertex. Run with --benchmark_counters_tabular=true
// --benchmark_repetitions=3 --benchmark_report_aggregates_only=true.
#include <benchmark/benchmark.h>

#include <map>
#include <tuple>
#include <memory>
#include <string>

#include "bench_scenes.hpp"
#include "stvd/tetgen/tetrahedralize.hpp"
#include "stvd/tetmesh/vertex_order.hpp"

namespace {

using namespace stvd;

/// Box [-20, 20] x [-16, 16] x [-12, 12] mm, radius-edge ratio 1.4.
struct TetScene {
  tetmesh::TetMesh mesh;
  CellMeshDomain domain;
  RiemannianMetric metric;
  VertexId source = 0;
  std::vector<double> exact;
};

const Vec3d kLow{-20, -16, -12}, kHigh{20, 16, 12};

test::TriangularPullbackMap curvedMap() {
  test::TriangularPullbackMap map;
  map.r = test::rotation({0.4, 0.3, -1.0}, 0.9);
  map.gamma = 12.0;
  map.a1 = 4.0;
  map.w1 = 2.0 * test::kPi / 96.0;
  map.a3 = 4.0;
  map.w3 = 2.0 * test::kPi / 96.0;
  return map;
}

/// maxVolume 0.2 gives the tests' 55k-vertex mesh, 0.02 about 490k vertices.
/// `morton`: vertices renumbered along a Morton curve (as `stvd distance`
/// does), otherwise in TetGen's order.
const TetScene& tetScene(int maxVolumeThousandths, bool curved, bool morton) {
  static std::map<std::tuple<int, bool, bool>, std::unique_ptr<TetScene>> scenes;
  auto& s = scenes[{maxVolumeThousandths, curved, morton}];
  if (s) return *s;
  tetgen::TetrahedralizeOptions o;
  o.quality = 1.4;
  o.maxVolume = maxVolumeThousandths / 1000.0;
  tetmesh::TetMesh mesh = tetgen::tetrahedralizeSurface(tetgen::boxSurface(kLow, kHigh), o, "box");
  if (morton) {
    const tetmesh::VertexPermutation p = tetmesh::mortonOrder(mesh.points);
    mesh.points = tetmesh::permutedPoints(mesh.points, p);
    mesh.tets = tetmesh::permutedTets(mesh.tets, p);
  }
  CellMeshDomain domain = CellMeshDomain::fromTetrahedra(mesh.points, mesh.tets);
  VertexId source = 0;
  for (VertexId v = 1; v < mesh.vertexCount(); ++v)
    if (norm(mesh.points[v] - Vec3d{1.3, -0.7, 0.4}) < norm(mesh.points[source] - Vec3d{1.3, -0.7, 0.4})) source = v;
  std::vector<double> exact(mesh.vertexCount());
  std::vector<SymTensor3> tensors(mesh.vertexCount());
  const test::Mat3 g = test::uniaxialTensor(12.0, {0.55, -0.45, 0.7});
  const test::TriangularPullbackMap map = curvedMap();
  for (VertexId v = 0; v < mesh.vertexCount(); ++v) {
    const Vec3d p = mesh.points[v];
    tensors[v] = test::toSymTensor(curved ? map.metric(p) : g);
    exact[v] = curved ? norm(map(p) - map(mesh.points[source])) : test::tensorNorm(g, p - mesh.points[source]);
  }
  s = std::make_unique<TetScene>(TetScene{std::move(mesh), std::move(domain), RiemannianMetric(std::move(tensors)),
                                          source, std::move(exact)});
  return *s;
}

void setLabel(benchmark::State& state, int k, const std::string& what) {
  state.SetLabel(what + (k == 0 ? " Dijkstra" : " STVD k=" + std::to_string(k)));
}

PropagationOptions optionsFor(int k) {
  PropagationOptions o;
  o.method = k == 0 ? Method::Dijkstra : Method::ShortTermVectorDijkstra;
  o.k = k == 0 ? 1 : k;
  return o;
}

void perEdge(benchmark::State& state, std::uint64_t edges) {
  state.counters["relaxed_edges"] = double(edges);
  state.counters["time_per_edge"] = benchmark::Counter(
      double(edges), benchmark::Counter::kIsIterationInvariantRate | benchmark::Counter::kInvert);
}

void tetMesh(benchmark::State& state) {
  const int volume = static_cast<int>(state.range(0));
  const bool curved = state.range(1) != 0;
  const int k = static_cast<int>(state.range(2));
  const bool morton = state.range(3) != 0;
  const TetScene& s = tetScene(volume, curved, morton);
  const PropagationOptions options = optionsFor(k);
  PropagationResult r;
  for (auto _ : state) {
    r = propagate(s.domain, s.metric, {s.source}, options);
    benchmark::DoNotOptimize(r.distance.data());
  }
  perEdge(state, r.relaxedEdges);
  test::RelativeErrors e;
  for (VertexId v = 0; v < s.domain.vertexCount(); ++v)
    if (v != s.source) e.add(r.distance[v], s.exact[v]);
  state.counters["mean_error"] = e.mean();
  state.counters["max_error"] = e.max();
  state.counters["vertices"] = double(s.domain.vertexCount());
  state.counters["edges_per_vertex"] = 2.0 * double(s.domain.edgeCount()) / double(s.domain.vertexCount());
  setLabel(state, k, std::string("tets ") + (curved ? "curved" : "constant") + (morton ? " morton" : " tetgen-order"));
}

/// The grid reference: 128^3, 26-neighbourhood, pull-back gamma 20 (the
/// scene of propagation_speed and docs/benchmarks.md).
void grid(benchmark::State& state) {
  const int k = static_cast<int>(state.range(0));
  static const bench::Scene s = bench::pullbackScene(128, 20.0, Stencil::full26(), 128);
  const PropagationOptions options = optionsFor(k);
  std::uint64_t edges = 0;
  for (auto _ : state) {
    PropagationResult r = propagate(s.domain, s.metric, {s.source}, options);
    edges = r.relaxedEdges;
    benchmark::DoNotOptimize(r.distance.data());
  }
  perEdge(state, edges);
  state.counters["vertices"] = double(s.domain.vertexCount());
  setLabel(state, k, "grid 128^3 26-nbh");
}

BENCHMARK(grid)->ArgNames({"k"})->Arg(0)->Arg(5)->Arg(8)->Unit(benchmark::kMillisecond);
BENCHMARK(tetMesh)
    ->ArgNames({"vol_milli", "curved", "k", "morton"})
    ->ArgsProduct({{200, 20}, {0, 1}, {0, 5, 8}, {0, 1}})
    ->Unit(benchmark::kMillisecond);

}  // namespace

BENCHMARK_MAIN();
