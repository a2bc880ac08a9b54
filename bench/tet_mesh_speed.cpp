// Tetrahedral meshes made by TetGen: time per relaxed edge of Dijkstra and
// STVD(k) next to the 128^3 grid with the 26-neighbourhood in the same run,
// and the errors of the ways to measure an STVD candidate on a mesh.
//
// tetMesh: quality meshes of a box at two sizes, constant gamma = 12 along
// an oblique axis ("constant", exact ||x - s||_G) or the curved pull-back of
// the tests, gamma = 12 ("curved", exact |phi(x) - phi(s)|; every vertex is
// counted: on the 55k mesh the tests find the straight image segment inside
// phi(box) for all of them); STVD with the default segment measure
// (measure 0) or the largest-norm rule (measure 1).
//
// tetMeshNotch: the same on a quality mesh of an L-shaped prism, which is
// not convex (below).
//
// tetMeshRule: the error table of docs/tet_meshes.md on the 55k box mesh
// (Morton order) and on a quality mesh of an L-shaped prism (constant metric
// diag(1, 4, 2.25), exact distance around its notch): the segment measure
// with one sample per tetrahedron crossed (rule 0, the default), one at the
// midpoint (1), or one per chain edge at the midpoints of equal pieces (2),
// and the chain rules largest-norm (3) and projection-weighted (4).
//
// Counters: time_per_edge (CPU seconds per relaxed edge: on a machine
// shared with other work, wall time measured up to twice the CPU time and
// varied from run to run), relaxed_edges, mean_error, max_error,
// min_signed (the most negative signed relative error), below (vertices
// more than 1e-5 below the exact distance), measured_per_vertex,
// refused, vertices, edges_per_vertex. Run with
// --benchmark_counters_tabular=true --benchmark_repetitions=3
// --benchmark_enable_random_interleaving=true (the repetitions of all
// benchmarks alternate).
#include <benchmark/benchmark.h>

#include <map>
#include <memory>
#include <string>
#include <tuple>

#include "../tests/tetmesh/l_shaped_prism_surface.hpp"
#include "bench_scenes.hpp"
#include "scenes.hpp"
#include "stvd/cell_mesh/cell_mesh_propagation.hpp"
#include "stvd/propagation/propagation_definition.hpp"
#include "stvd/tetgen/tetrahedralize.hpp"
#include "stvd/tetmesh/vertex_order.hpp"

namespace {

using namespace stvd;

/// The same mesh as a domain type of its own, whose candidates are measured
/// with another MeshSegmentSampling than CellMeshDomain's.
template <MeshSegmentSampling Sampling>
struct MeshWithSampling : CellMeshDomain {
  explicit MeshWithSampling(const CellMeshDomain& mesh) : CellMeshDomain(mesh) {}
};

}  // namespace

namespace stvd {
template <MeshSegmentSampling Sampling>
struct DomainHooks<MeshWithSampling<Sampling>> {
  template <class Norm>
  using CandidatePath = CellMeshCandidatePath<Norm, Sampling>;
  using ChainUnfolding = VolumeChainUnfolding<MeshWithSampling<Sampling>>;
  static constexpr int kDefaultMemoryDepth = stvd::kDefaultMemoryDepth;
  static constexpr bool kPrefetchesNeighborhood = false;
  static constexpr bool kChainContinuesAlongStep = false;
};
}  // namespace stvd

namespace {

struct TetScene {
  std::string name;
  CellMeshDomain domain;
  RiemannianMetric metric;
  VertexId source = 0;
  std::vector<double> exact;  // negative: not counted
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

VertexId vertexNearest(const std::vector<Vec3d>& points, Vec3d p) {
  VertexId best = 0;
  for (VertexId v = 1; v < points.size(); ++v)
    if (norm(points[v] - p) < norm(points[best] - p)) best = v;
  return best;
}

/// Vertices renumbered along a Morton curve, as `stvd distance` does.
void mortonOrder(tetmesh::TetMesh& mesh) {
  const tetmesh::VertexPermutation p = tetmesh::mortonOrder(mesh.points);
  mesh.points = tetmesh::permutedPoints(mesh.points, p);
  mesh.tets = tetmesh::permutedTets(mesh.tets, p);
}

/// maxVolume 0.2 gives the tests' 55k-vertex mesh, 0.02 about 490k vertices.
/// `morton`: vertices renumbered along a Morton curve, otherwise in TetGen's
/// order.
const TetScene& tetScene(int maxVolumeThousandths, bool curved, bool morton) {
  static std::map<std::tuple<int, bool, bool>, std::unique_ptr<TetScene>> scenes;
  auto& s = scenes[{maxVolumeThousandths, curved, morton}];
  if (s) return *s;
  tetgen::TetrahedralizeOptions o;
  o.quality = 1.4;
  o.maxVolume = maxVolumeThousandths / 1000.0;
  tetmesh::TetMesh mesh = tetgen::tetrahedralizeSurface(tetgen::boxSurface(kLow, kHigh), o, "box");
  if (morton) mortonOrder(mesh);
  const VertexId source = vertexNearest(mesh.points, {1.3, -0.7, 0.4});
  std::vector<double> exact(mesh.vertexCount(), -1.0);
  std::vector<SymTensor3> tensors(mesh.vertexCount());
  const test::Mat3 g = test::uniaxialTensor(12.0, {0.55, -0.45, 0.7});
  const test::TriangularPullbackMap map = curvedMap();
  for (VertexId v = 0; v < mesh.vertexCount(); ++v) {
    const Vec3d p = mesh.points[v];
    tensors[v] = test::toSymTensor(curved ? map.metric(p) : g);
    if (v != source)
      exact[v] = curved ? norm(map(p) - map(mesh.points[source])) : test::tensorNorm(g, p - mesh.points[source]);
  }
  s = std::make_unique<TetScene>(TetScene{curved ? "curved" : "constant",
                                          CellMeshDomain::fromTetrahedra(mesh.points, mesh.tets),
                                          RiemannianMetric(std::move(tensors)), source, std::move(exact)});
  return *s;
}

/// The L-shaped prism [0, 16] x [0, 16] x [0, 4] without the quadrant
/// x > 8, y > 8 (tetrahedra of at most 0.1 mm^3: the mesh of
/// tests/tetmesh/tetgen_box_accuracy_test.cpp), constant metric
/// diag(1, 4, 2.25), from the vertex nearest (15, 4, 1).
const TetScene& lShapedScene(int maxVolumeThousandths) {
  static std::map<int, std::unique_ptr<TetScene>> scenes;
  auto& s = scenes[maxVolumeThousandths];
  if (s) return *s;
  const tetgen::SurfaceMesh surface = test::lShapedPrismSurface();
  tetgen::TetrahedralizeOptions o;
  o.quality = 1.4;
  o.maxVolume = maxVolumeThousandths / 1000.0;
  tetmesh::TetMesh mesh = tetgen::tetrahedralizeSurface(surface, o, "L-shaped prism");
  mortonOrder(mesh);
  const VertexId source = vertexNearest(mesh.points, {15.0, 4.0, 1.0});
  std::vector<double> exact(mesh.vertexCount(), -1.0);
  for (VertexId v = 0; v < mesh.vertexCount(); ++v)
    if (v != source) exact[v] = test::lShapedPrismDistance(8.0, mesh.points[source], mesh.points[v], 1.0, 2.0, 1.5);
  s = std::make_unique<TetScene>(
      TetScene{"L-shaped", CellMeshDomain::fromTetrahedra(mesh.points, mesh.tets),
               RiemannianMetric::constant(mesh.vertexCount(), SymTensor3{1.f, 0.f, 0.f, 4.f, 0.f, 2.25f}), source,
               std::move(exact)});
  return *s;
}

std::string methodLabel(int k, ChainMeasure measure) {
  return k == 0 ? " Dijkstra" : " STVD k=" + std::to_string(k) + " " + chainMeasureName(measure);
}

PropagationOptions optionsFor(int k, ChainMeasure measure) {
  PropagationOptions o;
  o.method = k == 0 ? Method::Dijkstra : Method::ShortTermVectorDijkstra;
  o.k = k == 0 ? 1 : k;
  o.chainMeasure = measure;
  return o;
}

void perEdge(benchmark::State& state, std::uint64_t edges) {
  state.counters["relaxed_edges"] = double(edges);
  state.counters["time_per_edge"] = benchmark::Counter(
      double(edges), benchmark::Counter::kIsIterationInvariantRate | benchmark::Counter::kInvert);
}

void errorCounters(benchmark::State& state, const TetScene& s, const PropagationResult& r) {
  test::RelativeErrors e;
  double below = 0.0;
  for (VertexId v = 0; v < s.domain.vertexCount(); ++v) {
    if (s.exact[v] <= 0.0) continue;
    e.add(r.distance[v], s.exact[v]);
    below += r.distance[v] < (1.0 - 1e-5) * s.exact[v] ? 1.0 : 0.0;
  }
  state.counters["mean_error"] = e.mean();
  state.counters["max_error"] = e.max();
  state.counters["min_signed"] = e.minSigned();
  state.counters["below"] = below;
  state.counters["measured_per_vertex"] = double(r.measuredCandidates) / double(r.finalizedVertices);
  state.counters["refused"] = double(r.refusedCandidates);
  state.counters["vertices"] = double(s.domain.vertexCount());
}

/// Times the propagation of `options` over the scene and reports its time
/// per relaxed edge and its error.
PropagationResult timePropagation(benchmark::State& state, const TetScene& s, const PropagationOptions& options) {
  PropagationResult r;
  for (auto _ : state) {
    r = propagate(s.domain, s.metric, {s.source}, options);
    benchmark::DoNotOptimize(r.distance.data());
  }
  perEdge(state, r.relaxedEdges);
  errorCounters(state, s, r);
  return r;
}

constexpr ChainMeasure kMeasures[] = {ChainMeasure::Segment, ChainMeasure::LargestEdgeNorm};

void tetMesh(benchmark::State& state) {
  const int volume = static_cast<int>(state.range(0));
  const bool curved = state.range(1) != 0;
  const int k = static_cast<int>(state.range(2));
  const bool morton = state.range(3) != 0;
  const ChainMeasure measure = kMeasures[state.range(4)];
  const TetScene& s = tetScene(volume, curved, morton);
  timePropagation(state, s, optionsFor(k, measure));
  state.counters["edges_per_vertex"] = 2.0 * double(s.domain.edgeCount()) / double(s.domain.vertexCount());
  state.SetLabel("tets " + s.name + (morton ? " morton" : " tetgen-order") + methodLabel(k, measure));
}

/// Dijkstra, then STVD k = 4, 6 and 8 with each measure, per mesh and metric.
void tetMeshArguments(benchmark::internal::Benchmark* b) {
  for (int volume : {200, 20})
    for (int curved : {0, 1})
      for (int morton : {0, 1}) {
        b->Args({volume, curved, 0, morton, 0});
        for (int k : {4, 6, 8})
          for (int measure : {0, 1}) b->Args({volume, curved, k, morton, measure});
      }
}

template <class Domain>
PropagationResult propagateAs(const TetScene& s, const PropagationOptions& options) {
  static std::map<const TetScene*, std::unique_ptr<Domain>> copies;
  auto& d = copies[&s];
  if (!d) d = std::make_unique<Domain>(s.domain);
  return propagate(*d, s.metric, {s.source}, options);
}

void tetMeshRule(benchmark::State& state) {
  const int scene = static_cast<int>(state.range(0));
  const int rule = static_cast<int>(state.range(1));
  const int k = static_cast<int>(state.range(2));
  const TetScene& s = scene == 2 ? lShapedScene(100) : tetScene(200, scene == 1, true);
  const ChainMeasure measure = rule == 3 ? ChainMeasure::LargestEdgeNorm
                               : rule == 4 ? ChainMeasure::ProjectionWeighted
                                           : ChainMeasure::Segment;
  const PropagationOptions options = optionsFor(k, measure);
  PropagationResult r;
  for (auto _ : state) {
    if (rule == 1) r = propagateAs<MeshWithSampling<MeshSegmentSampling::Midpoint>>(s, options);
    else if (rule == 2) r = propagateAs<MeshWithSampling<MeshSegmentSampling::EqualPieces>>(s, options);
    else r = propagate(s.domain, s.metric, {s.source}, options);
    benchmark::DoNotOptimize(r.distance.data());
  }
  perEdge(state, r.relaxedEdges);
  errorCounters(state, s, r);
  const char* rules[] = {" per tetrahedron", " midpoint", " equal pieces", "", ""};
  state.SetLabel(s.name + methodLabel(k, measure) + rules[rule]);
}

/// Dijkstra and STVD k = 8 with each measure on a larger mesh of the
/// L-shaped prism (0.01 mm^3), which is not convex: candidates near its
/// notch are walked when they are relaxed, to be refused if they leave it.
void tetMeshNotch(benchmark::State& state) {
  const int k = static_cast<int>(state.range(0));
  const ChainMeasure measure = kMeasures[state.range(1)];
  const TetScene& s = lShapedScene(10);
  timePropagation(state, s, optionsFor(k, measure));
  state.SetLabel("tets " + s.name + " morton" + methodLabel(k, measure));
}

/// The 128^3 grid with the 26-neighbourhood, pull-back gamma 20 (the scene
/// of propagation_speed and docs/benchmarks.md): the reference for the time
/// per edge.
void grid(benchmark::State& state) {
  const int k = static_cast<int>(state.range(0));
  static const bench::Scene s = bench::pullbackScene(128, 20.0, Stencil::full26(), 128);
  const PropagationOptions options = optionsFor(k, kDefaultChainMeasure);
  std::uint64_t edges = 0;
  for (auto _ : state) {
    PropagationResult r = propagate(s.domain, s.metric, {s.source}, options);
    edges = r.relaxedEdges;
    benchmark::DoNotOptimize(r.distance.data());
  }
  perEdge(state, edges);
  state.counters["vertices"] = double(s.domain.vertexCount());
  state.SetLabel("grid 128^3 26-nbh" + methodLabel(k, kDefaultChainMeasure));
}

BENCHMARK(grid)->ArgNames({"k"})->Arg(0)->Arg(kDefaultMemoryDepth)->Unit(benchmark::kMillisecond);
BENCHMARK(tetMesh)
    ->ArgNames({"vol_milli", "curved", "k", "morton", "measure"})
    ->Apply(tetMeshArguments)
    ->Unit(benchmark::kMillisecond);
BENCHMARK(tetMeshNotch)
    ->ArgNames({"k", "measure"})
    ->Args({0, 0})
    ->Args({8, 0})
    ->Args({8, 1})
    ->Unit(benchmark::kMillisecond);
// Accuracy, not time: one run each.
BENCHMARK(tetMeshRule)
    ->ArgNames({"scene", "rule", "k"})
    ->ArgsProduct({{0, 1, 2}, {0, 1, 2, 3, 4}, {2, 4, 6, 8, 12, 16}})
    ->Iterations(1)
    ->Repetitions(1)
    ->Unit(benchmark::kMillisecond);

}  // namespace

BENCHMARK_MAIN();
