// Prints the surface table of docs/surfaces.md and docs/benchmarks.md:
// Dijkstra, STVD (the segment measure at several k, and the paper's rule)
// and Lanthier's Steiner points on a real triangle mesh, against a
// reference, with times as ratios to Dijkstra's taken in the same process.
//
//   stvd_surface_exact_table MESH.off --source N --exact FILE
//       isotropic, against the exact polyhedral distances in FILE (one per
//       vertex, as tests/surface/exact_geodesic_oracle.cpp writes them)
//   stvd_surface_exact_table MESH.off --source N --curvature G
//       the curvature metric of anisotropy G, against Lanthier M = 16
//   [--repeats R] (timing: the methods alternate R times, medians)
//   [--no-header]
//
// One tab-separated row per method: mesh, metric, source, method, mean
// relative error, mean signed error, max error, vertices below the
// reference by more than 1e-5 (isotropic) or 1 % (anisotropic) relative,
// the most negative signed error, propagation time / Dijkstra's, whole
// process (mesh read, surface built, metric, propagation) / Dijkstra's,
// measured and refused candidates per vertex.
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <functional>
#include <string>
#include <vector>

#include "stvd/propagation/propagation.hpp"
#include "stvd/lanthier/lanthier_propagation.hpp"
#include "stvd/surface_io/surface_mesh_io.hpp"
#include "stvd/surface/surface_metrics.hpp"
#include "stvd/surface/surface_propagation.hpp"
#include "stvd/surface/surface_lanthier.hpp"

namespace {

using namespace stvd;
using Clock = std::chrono::steady_clock;

double seconds(Clock::time_point a, Clock::time_point b) { return std::chrono::duration<double>(b - a).count(); }

double median(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  return v.empty() ? 0.0 : v[v.size() / 2];
}

struct Run {
  std::string name;
  std::function<PropagationResult()> run;
  std::vector<double> times;
  PropagationResult result;
};

[[noreturn]] void usage() {
  std::fprintf(stderr,
               "usage: stvd_surface_exact_table MESH.off --source N (--exact FILE | --curvature G) "
               "[--repeats R] [--no-header]\n");
  std::exit(2);
}

}  // namespace

int main(int argc, char** argv) {
  std::string meshPath, exactPath;
  long source = -1;
  double curvature = 0.0;
  int repeats = 3;
  bool header = true;
  for (int a = 1; a < argc; ++a) {
    auto value = [&] {
      if (a + 1 >= argc) usage();
      return std::string(argv[++a]);
    };
    if (!std::strcmp(argv[a], "--source")) source = std::atol(value().c_str());
    else if (!std::strcmp(argv[a], "--exact")) exactPath = value();
    else if (!std::strcmp(argv[a], "--curvature")) curvature = std::atof(value().c_str());
    else if (!std::strcmp(argv[a], "--repeats")) repeats = std::atoi(value().c_str());
    else if (!std::strcmp(argv[a], "--no-header")) header = false;
    else if (argv[a][0] != '-' && meshPath.empty()) meshPath = argv[a];
    else usage();
  }
  if (meshPath.empty() || source < 0 || (exactPath.empty() == (curvature < 1.0)) || repeats < 1) usage();

  // The whole process's fixed part, timed as the tool runs it.
  std::vector<double> setupTimes;
  auto setup = [&] {
    const auto t0 = Clock::now();
    surface_io::SurfaceMesh mesh = surface_io::readSurfaceMesh(meshPath);
    SurfaceDomain surface(std::move(mesh.points), mesh.faces);
    RiemannianMetric metric = curvature >= 1.0 ? curvatureMetric(surface, curvature) : isotropicSurfaceMetric(surface);
    setupTimes.push_back(seconds(t0, Clock::now()));
    return std::make_pair(std::move(surface), std::move(metric));
  };
  auto [surface, metric] = setup();
  for (int r = 1; r < repeats; ++r) setup();
  if (source >= static_cast<long>(surface.vertexCount())) {
    std::fprintf(stderr, "stvd_surface_exact_table: %s has no vertex %ld\n", meshPath.c_str(), source);
    return 2;
  }
  const std::vector<VertexId> sources{static_cast<VertexId>(source)};

  std::vector<double> reference;
  const bool isotropic = curvature < 1.0;
  if (isotropic) {
    std::ifstream in(exactPath);
    for (double x; in >> x;) reference.push_back(x);
    if (reference.size() != surface.vertexCount()) {
      std::fprintf(stderr, "stvd_surface_exact_table: %s holds %zu distances for %u vertices\n", exactPath.c_str(),
                   reference.size(), surface.vertexCount());
      return 2;
    }
  } else {
    LanthierOptions o;
    o.steinerPoints = 16;
    reference = lanthierPropagate(surface, metric, sources, o).distance;
  }

  std::vector<Run> methods;
  auto add = [&](const std::string& name, PropagationOptions o) {
    methods.push_back({name, [&surface = surface, &metric = metric, &sources, o] {
                         return propagate(surface, metric, sources, o);
                       }, {}, {}});
  };
  {
    PropagationOptions o;
    o.method = Method::Dijkstra;
    add("Dijkstra", o);
  }
  for (const int k : {2, 4, 8, 12, 16}) {
    PropagationOptions o;
    o.k = k;
    add("STVD k = " + std::to_string(k), o);
  }
  {
    PropagationOptions o;
    o.k = 8;
    o.chainMeasure = ChainMeasure::ProjectionWeighted;
    add("STVD k = 8, paper's rule", o);
  }
  for (const int m : {4, 8}) {
    methods.push_back({"Lanthier M = " + std::to_string(m), [&surface = surface, &metric = metric, &sources, m] {
                         LanthierOptions o;
                         o.steinerPoints = m;
                         return static_cast<PropagationResult>(lanthierPropagate(surface, metric, sources, o));
                       }, {}, {}});
  }
  for (int r = 0; r < repeats; ++r)
    for (Run& m : methods) {
      const auto t0 = Clock::now();
      m.result = m.run();
      m.times.push_back(seconds(t0, Clock::now()));
    }

  const double dijkstra = median(methods[0].times), fixed = median(setupTimes);
  std::string meshName = meshPath.substr(meshPath.find_last_of('/') + 1);
  meshName = meshName.substr(0, meshName.find('.'));
  const std::string metricName = isotropic ? "isotropic" : "curvature " + std::to_string(int(curvature));
  const double belowLimit = isotropic ? 1e-5 : 1e-2;
  if (header)
    std::printf("mesh\tvertices\tmetric\tsource\tmethod\tmean\tmean_signed\tmax\tbelow\tmin_signed\t"
                "propagation_ratio\twhole_ratio\tmeasured_per_vertex\trefused_per_vertex\tdijkstra_seconds\n");
  for (const Run& m : methods) {
    double sum = 0.0, signedSum = 0.0, worst = 0.0, minSigned = 0.0;
    std::size_t count = 0, below = 0;
    for (VertexId v = 0; v < surface.vertexCount(); ++v) {
      const double x = reference[v], y = m.result.distance[v];
      if (!(x > 1e-12) || !std::isfinite(x) || !std::isfinite(y)) continue;
      const double e = (y - x) / x;
      sum += std::abs(e);
      signedSum += e;
      worst = std::max(worst, std::abs(e));
      minSigned = std::min(minSigned, e);
      below += e < -belowLimit ? 1 : 0;
      ++count;
    }
    const double t = median(m.times);
    std::printf("%s\t%u\t%s\t%ld\t%s\t%.4g\t%.4g\t%.4g\t%zu\t%.3g\t%.3g\t%.3g\t%.3f\t%.3f\t%.4f\n", meshName.c_str(),
                surface.vertexCount(), metricName.c_str(), source, m.name.c_str(), sum / count, signedSum / count,
                worst, below, minSigned, t / dijkstra, (fixed + t) / (fixed + dijkstra),
                double(m.result.measuredCandidates) / surface.vertexCount(),
                double(m.result.refusedCandidates) / surface.vertexCount(), dijkstra);
  }
  return 0;
}
