// Prints the error-versus-time table of Lanthier's Steiner-point
// propagation on a polygon surface next to Dijkstra and STVD
// (docs/steiner.md, "Surfaces and tetrahedral meshes"): the curved height
// field z = 0.5 sin(x) cos(y) of tests/surface (badly shaped triangles,
// columns 1 : 0.15, jitter 0.6) under the pull-back of the plane's
// diag(1, 16), whose exact distance is sqrt(dx^2 + 16 dy^2), and the same
// triangulation flat under a constant metric of anisotropy 6. Per row: mean
// and max relative error over all vertices but the seed, seconds (one run),
// relaxed edges (segments evaluated, for Steiner), graph points and peak
// propagation state.
//
//   stvd_surface_steiner_table [--size N] [--max-steiner M]
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <functional>
#include <string>
#include <vector>

#include "relative_error.hpp"
#include "stvd/propagation/propagation.hpp"
#include "stvd/lanthier/lanthier_propagation.hpp"
#include "stvd/surface/surface_metrics.hpp"
#include "stvd/surface/surface_propagation.hpp"
#include "stvd/surface/surface_lanthier.hpp"
#include "steiner_table_format.hpp"
#include "surface_meshes.hpp"

namespace {

using namespace stvd;

struct SurfaceScene {
  std::string name;
  test::GeneratedSurface mesh;
  SurfaceDomain surface;
  RiemannianMetric metric;
  VertexId source;
  std::function<double(VertexId)> exact;
};

void row(const SurfaceScene& scene, const std::string& label, const PropagationResult& r, std::uint64_t points,
         double seconds) {
  test::RelativeErrors e;
  for (VertexId v = 0; v < scene.surface.vertexCount(); ++v) {
    const double x = scene.exact(v);
    if (x > 1e-9) e.add(r.distance[v], x);
  }
  bench::printSteinerTableRow(label, e, r, points, seconds);
}

void table(const SurfaceScene& scene, int maxSteiner) {
  std::printf("\n#### %s (%u vertices, %zu faces)\n\n", scene.name.c_str(), scene.surface.vertexCount(),
              scene.surface.faceCount());
  bench::printSteinerTableHeader();
  const std::vector<VertexId> sources{scene.source};
  PropagationResult r;
  PropagationOptions o;
  o.method = Method::Dijkstra;
  o.k = 1;
  double s = bench::timedSeconds([&] { r = propagate(scene.surface, scene.metric, sources, o); });
  row(scene, "Dijkstra", r, scene.surface.vertexCount(), s);
  o.method = Method::ShortTermVectorDijkstra;
  for (const ChainMeasure measure : {ChainMeasure::Segment, ChainMeasure::ProjectionWeighted}) {
    o.chainMeasure = measure;
    for (int k : {5, 8}) {
      o.k = k;
      s = bench::timedSeconds([&] { r = propagate(scene.surface, scene.metric, sources, o); });
      row(scene, "STVD k = " + std::to_string(k) + " (" + chainMeasureName(measure) + ")", r,
          scene.surface.vertexCount(), s);
    }
  }
  bench::printLanthierRows(scene.surface, scene.metric, sources, maxSteiner,
                           [&](const std::string& label, const PropagationResult& result, std::uint64_t points,
                               double seconds) { row(scene, label, result, points, seconds); });
}

}  // namespace

int main(int argc, char** argv) {
  int size = 96, maxSteiner = 16;
  for (int a = 1; a < argc; ++a) {
    auto value = [&](const char* name) {
      if (a + 1 >= argc) {
        std::fprintf(stderr, "stvd_surface_steiner_table: %s needs a value\n", name);
        std::exit(2);
      }
      return argv[++a];
    };
    if (!std::strcmp(argv[a], "--size")) {
      size = std::atoi(value("--size"));
    } else if (!std::strcmp(argv[a], "--max-steiner")) {
      maxSteiner = std::atoi(value("--max-steiner"));
    } else {
      std::fprintf(stderr, "usage: stvd_surface_steiner_table [--size N] [--max-steiner M]\n");
      return 2;
    }
  }
  if (size < 4 || maxSteiner < 1 || maxSteiner > kMaxSteinerPoints) {
    std::fprintf(stderr, "stvd_surface_steiner_table: --size must be at least 4 and --max-steiner within 1..%d\n",
                 kMaxSteinerPoints);
    return 2;
  }
  const double pi = test::kPi;
  std::printf("### Lanthier's Steiner points on surfaces against Dijkstra and STVD\n");
  {
    test::GeneratedSurface mesh = test::planeMesh(size, size, 2.0 * pi, 2.0 * pi, 0.15, 0.6, false, 21);
    for (std::size_t v = 0; v < mesh.points.size(); ++v)
      mesh.points[v].z = 0.5 * std::sin(mesh.flat[v][0]) * std::cos(mesh.flat[v][1]);
    SurfaceDomain surface(mesh.points, mesh.faces);
    RiemannianMetric metric = surfaceMetricFromWorldTensors(
        surface, std::vector<SymTensor3>(surface.vertexCount(), SymTensor3{1, 0, 0, 16, 0, 0}));
    const VertexId source = test::nearestFlatVertex(mesh, pi, pi);
    SurfaceScene scene{"height field z = 0.5 sin x cos y, " + std::to_string(size) + " x " + std::to_string(size) +
                           " badly shaped, pull-back of diag(1, 16)",
                       mesh, std::move(surface), std::move(metric), source, nullptr};
    scene.exact = [&scene](VertexId v) {
      const auto& f = scene.mesh.flat;
      return std::hypot(f[v][0] - f[scene.source][0], 4.0 * (f[v][1] - f[scene.source][1]));
    };
    table(scene, maxSteiner);
  }
  {
    const test::GeneratedSurface mesh = test::planeMesh(size, size, 2.0 * pi, 2.0 * pi, 0.15, 0.6, false, 21);
    const SurfaceDomain surface(mesh.points, mesh.faces);
    const auto g = test::tensor2(6.0, 0.5);
    const float g11 = float(g[0]), g12 = float(g[1]), g22 = float(g[2]);
    RiemannianMetric metric = surfaceMetricFromWorldTensors(
        surface, std::vector<SymTensor3>(surface.vertexCount(), SymTensor3{g11, g12, 0, g22, 0, 0}));
    const VertexId source = test::nearestFlatVertex(mesh, pi, pi);
    SurfaceScene scene{"flat, same triangulation, constant metric of anisotropy 6", mesh, surface,
                       std::move(metric), source, nullptr};
    scene.exact = [&scene, g](VertexId v) {
      const auto& f = scene.mesh.flat;
      return test::norm2(g, f[v][0] - f[scene.source][0], f[v][1] - f[scene.source][1]);
    };
    table(scene, maxSteiner);
  }
  return 0;
}
