// The measurements behind docs/benchmarks.md, as tab-separated rows on
// standard output (scripts/evaluate.sh runs this tool, plots the rows and
// writes the document). One experiment per call:
//
//   sweep       error versus run time on the constant and the curved
//               (pull-back) exact metric at each anisotropy: Dijkstra on
//               every stencil, STVD for k = 2..16 on the 26-neighbourhood
//               with each chain measure (the segment measure, the default;
//               the paper's rule; the largest-norm rule), and with
//               --steiner-max M Lanthier's Steiner points for M = 1, 2, 4,
//               ... up to M (one run each: they take seconds to minutes).
//   refinement  the 3D version of the paper's section 6.1 experiment: the
//               grid is refined by 2 per level while k grows by less than 2.
//   convergence the same box refined three times (32^3, 64^3, 128^3) at the
//               library's defaults: the constant metric with eigenvalue 1
//               along (1, 2, 3)/sqrt(14) and (25, 25) or (25, 625) across,
//               and the curved scene (gamma 20); Dijkstra, default STVD,
//               STVD without source factoring (the source's reach that of
//               any ancestor) and with its chain of edges alone (no
//               any-angle ancestor, as before issue 33).
//   options     the curved scene (gamma 20) at --size N under the options
//               of the any-angle ancestors and k: the default, k = 8, 12,
//               16, two and four ancestors, segment reaches of 12 and 24
//               steps, all at once; and Dijkstra.
//   bend        the curved scene at --size N for each gamma of --gammas
//               and the shear slopes 0.1, 0.25 (the other experiments')
//               and 0.49: how the default's errors grow with the
//               anisotropy and with the bend of the metric's cheap sheets;
//               scene "curved-slope-S", gamma the map's.
//   plane       a flat plane under a constant anisotropic metric
//               (eigenvalues 1 and 16, axes at 30 degrees), regular and
//               Delaunay triangulations: the surface default (segment
//               measure, k = 8) against the paper's rule, k = 8 and 16.
//   phantom     writes a scene for scripts/hfm_comparison.py: its metric as
//               a NRRD tensor file (--out PREFIX.nrrd), its exact distances
//               (PREFIX.exact, float64 per voxel, x fastest, -1 where none)
//               and its seed (PREFIX.seed: i j k). --scene constant,
//               rotated25, rotated625 or curved.
//   scale       one default STVD run on an n^3 grid with a full tensor
//               field; reports time and the process's peak resident memory
//               (input included). Run once per size, each in a new process.
//   mask        default STVD on a 128^3 grid restricted to centred balls
//               holding a decreasing fraction of the voxels.
//   parallel    many source sets (8 balls of seeds, as the regions of a
//               connectivity run) propagated with propagateEachSourceSet on
//               1 and on 2 threads; checks that both give bit-identical
//               distances (exit status 3 otherwise) and reports each wall
//               time (parameter = threads).
//
//   stvd_evaluation EXPERIMENT [--size N] [--gammas G1,G2,...] [--repeats R]
//                   [--steiner-max M] [--no-header] [--scene S --out PREFIX]
//
// Every row has the mean and largest relative error over the voxels with an
// exact distance, and the mean, 99th percentile and largest over those more
// than 3 voxels from the source (the near-seed voxels, where a relative
// error has a tiny denominator, left out).
//
// Times are wall seconds of the propagation alone (scene construction
// excluded), the median of R runs.
#include <sys/resource.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <limits>
#include <sstream>
#include <string>
#include <vector>

#include "bench_scenes.hpp"
#include "scenes.hpp"
#include "stvd/lanthier/lanthier_propagation.hpp"
#include "stvd/propagation/source_set_propagation.hpp"
#include "stvd/surface/surface_domain.hpp"
#include "stvd/surface/surface_metrics.hpp"
#include "stvd/surface/surface_propagation.hpp"
#include "stvd/voxel_grid/voxel_grid_lanthier.hpp"
#include "stvd/voxel_grid/voxel_grid_propagation.hpp"
#include "surface_meshes.hpp"

namespace {

using namespace stvd;

struct Measured {
  PropagationResult result;
  double seconds = 0.0;
};

Measured measure(const VoxelGridDomain& domain, const RiemannianMetric& metric, VertexId source,
                 const PropagationOptions& options, int repeats) {
  std::vector<double> seconds;
  Measured m;
  for (int r = 0; r < repeats; ++r) {
    const auto start = std::chrono::steady_clock::now();
    m.result = propagate(domain, metric, {source}, options);
    seconds.push_back(std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count());
  }
  std::sort(seconds.begin(), seconds.end());
  m.seconds = seconds[seconds.size() / 2];
  return m;
}

std::uint64_t peakResidentBytes() {
  rusage usage{};
  getrusage(RUSAGE_SELF, &usage);
  return static_cast<std::uint64_t>(usage.ru_maxrss) * 1024u;  // Linux reports KiB
}

void header() {
  std::printf("experiment\tscene\tgamma\tn\tstencil\tmethod\tparameter\tdomain_voxels\t"
              "mean_rel_error\tmax_rel_error\tseconds\trelaxed_edges\tns_per_edge\t"
              "state_bytes\tpeak_rss_bytes\tmean_rel_error_far\tp99_rel_error_far\tmax_rel_error_far\t"
              "measured_per_vertex\n");
}

/// The relative errors over the voxels more than 3 voxels (index steps)
/// from the source: mean, 99th percentile, largest.
struct FarErrors {
  double mean = std::nan(""), p99 = std::nan(""), max = std::nan("");
};

FarErrors farErrorsOf(const bench::Scene& s, const PropagationResult& r) {
  const VoxelIndex c = s.domain.indexOf(s.source);
  std::vector<double> e;
  for (VertexId v = 0; v < s.domain.vertexCount(); ++v) {
    if (!(s.exact[v] > 0.0)) continue;
    const VoxelIndex x = s.domain.indexOf(v);
    const double di = x.i - c.i, dj = x.j - c.j, dk = x.k - c.k;
    if (di * di + dj * dj + dk * dk <= 9.0) continue;
    e.push_back(std::isfinite(r.distance[v]) ? std::abs(r.distance[v] - s.exact[v]) / s.exact[v]
                                             : std::numeric_limits<double>::infinity());
  }
  FarErrors f;
  if (e.empty()) return f;
  std::sort(e.begin(), e.end());
  double sum = 0.0;
  for (double x : e) sum += x;
  f.mean = sum / static_cast<double>(e.size());
  f.p99 = e[(e.size() - 1) * 99 / 100];
  f.max = e.back();
  return f;
}

/// One row. Errors are NaN where the scene has no exact distances.
void row(const char* experiment, const char* scene, double gamma, const VoxelGridDomain& domain,
         const char* method, int parameter, const test::RelativeErrors* errors,
         const Measured& m, const FarErrors& far = {}) {
  const double nan = std::nan("");
  std::printf("%s\t%s\t%g\t%zu\t%d\t%s\t%d\t%u\t%.6g\t%.6g\t%.6g\t%llu\t%.4g\t%llu\t%llu\t%.6g\t%.6g\t%.6g\t%.4g\n",
              experiment, scene, gamma, domain.geometry().size[0], domain.stencil().size(), method,
              parameter, domain.domainVertexCount(), errors ? errors->mean() : nan,
              errors ? errors->max() : nan, m.seconds,
              static_cast<unsigned long long>(m.result.relaxedEdges),
              1e9 * m.seconds / double(std::max<std::uint64_t>(m.result.relaxedEdges, 1)),
              static_cast<unsigned long long>(m.result.peakStateBytes),
              static_cast<unsigned long long>(peakResidentBytes()), far.mean, far.p99, far.max,
              double(m.result.measuredCandidates) / double(std::max<std::uint64_t>(m.result.finalizedVertices, 1)));
  std::fflush(stdout);
}

PropagationOptions dijkstraOptions() {
  PropagationOptions o;
  o.method = Method::Dijkstra;
  return o;
}

PropagationOptions stvdOptions(int k, ChainMeasure measure = kDefaultChainMeasure) {
  PropagationOptions o;
  o.method = Method::ShortTermVectorDijkstra;
  o.k = k;
  o.chainMeasure = measure;
  return o;
}

const char* measureName(ChainMeasure m) {
  return m == ChainMeasure::Segment ? "STVD-segment" : m == ChainMeasure::ProjectionWeighted ? "STVD-paper" : "STVD-largest";
}

/// The curved scene used throughout: pull-back metric with shear slope 0.25
/// (bent anisotropy directions; docs/benchmarks.md gives slopes 0.1 and 0.49).
constexpr double kCurvedSlope = 0.25;

bench::Scene makeScene(const std::string& kind, int n, double gamma, const Stencil& stencil) {
  if (kind == "constant") return bench::constantScene(n, gamma, stencil);
  return bench::pullbackScene(n, gamma, stencil, 1, kCurvedSlope);
}

Measured measureSteiner(const bench::Scene& s, int steinerPoints) {
  LanthierOptions o;
  o.steinerPoints = steinerPoints;
  Measured m;
  const auto start = std::chrono::steady_clock::now();
  m.result = lanthierPropagate(s.domain, s.metric, {s.source}, o);
  m.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return m;
}

void sweep(int n, const std::vector<double>& gammas, int repeats, int steinerMax) {
  for (const char* kind : {"constant", "curved"}) {
    for (double gamma : gammas) {
      for (const char* stencilName : {"6", "18", "26", "98", "290"}) {
        const bench::Scene s = makeScene(kind, n, gamma, Stencil::byName(stencilName));
        const Measured m = measure(s.domain, s.metric, s.source, dijkstraOptions(), repeats);
        const test::RelativeErrors e = s.errorsOf(m.result);
        row("sweep", kind, gamma, s.domain, "Dijkstra", 0, &e, m, farErrorsOf(s, m.result));
        if (std::string(stencilName) != "26") continue;
        for (ChainMeasure cm : {ChainMeasure::Segment, ChainMeasure::ProjectionWeighted, ChainMeasure::LargestEdgeNorm}) {
          for (int k = 2; k <= kMaxMemoryDepth; ++k) {
            const Measured mk = measure(s.domain, s.metric, s.source, stvdOptions(k, cm), repeats);
            const test::RelativeErrors ek = s.errorsOf(mk.result);
            row("sweep", kind, gamma, s.domain, measureName(cm), k, &ek, mk, farErrorsOf(s, mk.result));
          }
        }
        for (int m = 1; m <= steinerMax; m *= 2) {
          const Measured ms = measureSteiner(s, m);
          const test::RelativeErrors em = s.errorsOf(ms.result);
          row("sweep", kind, gamma, s.domain, "Lanthier", m, &em, ms, farErrorsOf(s, ms.result));
        }
      }
    }
  }
}

void refinement(int repeats) {
  // k grows by 3/2, 5/3, 8/5: each less than the factor 2 of the resolution.
  const int sizes[] = {16, 32, 64, 128};
  const int depths[] = {2, 3, 5, 8};
  for (const char* kind : {"constant", "curved"}) {
    const double gamma = std::string(kind) == "constant" ? 10.0 : 20.0;
    for (int level = 0; level < 4; ++level) {
      const bench::Scene s = makeScene(kind, sizes[level], gamma, Stencil::full26());
      const Measured d = measure(s.domain, s.metric, s.source, dijkstraOptions(), repeats);
      const test::RelativeErrors ed = s.errorsOf(d.result);
      row("refinement", kind, gamma, s.domain, "Dijkstra", 0, &ed, d, farErrorsOf(s, d.result));
      const Measured m = measure(s.domain, s.metric, s.source, stvdOptions(depths[level]), repeats);
      const test::RelativeErrors e = s.errorsOf(m.result);
      row("refinement", kind, gamma, s.domain, measureName(kDefaultChainMeasure), depths[level], &e, m,
          farErrorsOf(s, m.result));
    }
  }
}

/// G with eigenvalue 1 along (1, 2, 3)/sqrt(14) and `middle`, `expensive`
/// along (-2, 1, 0)/sqrt(5) and the third axis.
test::Mat3 rotatedTensor(double middle, double expensive) {
  const Vec3d a = test::normalized({1, 2, 3}), b = test::normalized({-2, 1, 0});
  const Vec3d c{a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x};
  const Vec3d axes[3] = {a, b, c};
  const double lambda[3] = {1.0, middle, expensive};
  test::Mat3 g;
  for (int r = 0; r < 3; ++r)
    for (int q = 0; q < 3; ++q) {
      double sum = 0.0;
      for (int m = 0; m < 3; ++m) sum += lambda[m] * (&axes[m].x)[r] * (&axes[m].x)[q];
      g(r, q) = sum;
    }
  return g;
}

/// The constant metric of rotatedTensor on an n^3 grid, source at the centre.
bench::Scene rotatedScene(int n, double middle, double expensive) {
  VoxelGridDomain domain(bench::cube(n), Stencil::full26());
  const test::Mat3 g = rotatedTensor(middle, expensive);
  bench::Scene s{"rotated", domain, RiemannianMetric::constant(domain.vertexCount(), test::toSymTensor(g)),
                 domain.vertexAt(n / 2, n / 2, n / 2), {}, std::sqrt(expensive)};
  const Vec3d x0 = domain.physicalPoint(s.source);
  s.exact.resize(domain.vertexCount());
  for (VertexId v = 0; v < domain.vertexCount(); ++v)
    s.exact[v] = v == s.source ? -1.0 : test::tensorNorm(g, domain.physicalPoint(v) - x0);
  return s;
}

bench::Scene namedScene(const std::string& name, int n) {
  if (name == "rotated25") return rotatedScene(n, 25.0, 25.0);
  if (name == "rotated625") return rotatedScene(n, 25.0, 625.0);
  if (name == "constant") return bench::constantScene(n, 20.0, Stencil::full26());
  return bench::pullbackScene(n, 20.0, Stencil::full26(), 1, kCurvedSlope);
}

void convergence(int repeats, int largest) {
  for (const char* scene : {"rotated25", "rotated625", "curved"}) {
    for (int n = 32; n <= largest; n *= 2) {
      const bench::Scene s = namedScene(scene, n);
      const double gamma = s.maxAnisotropy;
      auto run = [&](const char* method, const PropagationOptions& o) {
        const Measured m = measure(s.domain, s.metric, s.source, o, repeats);
        const test::RelativeErrors e = s.errorsOf(m.result);
        row("convergence", scene, gamma, s.domain, method, memoryDepth<VoxelGridDomain>(o), &e, m,
            farErrorsOf(s, m.result));
      };
      run("Dijkstra", dijkstraOptions());
      run("STVD-default", PropagationOptions{});
      PropagationOptions noFactoring;
      noFactoring.sourceReach = anyAngleReach(s.domain.domainVertexCount(), false);
      run("STVD-no-source-factoring", noFactoring);
      PropagationOptions chain;
      chain.anyAngleAncestors = 0;
      run("STVD-chain-alone", chain);
    }
  }
}

/// The options of the any-angle ancestors and k against each other on the
/// curved scene at n^3 (issue 33's question whether longer memories or
/// reaches bound the tails): the default, k = 8, 12, 16, two and four
/// ancestors, segment reaches of 12 and 24 steps, and all of them at once.
void options(int n, int repeats) {
  const bench::Scene s = namedScene("curved", n);
  struct Variant {
    const char* name;
    int k, ancestors, reach;  // reach 0: the default
  };
  const Variant variants[] = {{"STVD-default", 6, kDefaultAnyAngleAncestors, 0},
                              {"STVD-k8", 8, kDefaultAnyAngleAncestors, 0},
                              {"STVD-k12", 12, kDefaultAnyAngleAncestors, 0},
                              {"STVD-k16", 16, kDefaultAnyAngleAncestors, 0},
                              {"STVD-2-ancestors", 6, 2, 0},
                              {"STVD-4-ancestors", 6, 4, 0},
                              {"STVD-reach-12", 6, kDefaultAnyAngleAncestors, 12},
                              {"STVD-reach-24", 6, kDefaultAnyAngleAncestors, 24},
                              {"STVD-k12-4-ancestors-reach-24", 12, 4, 24}};
  const Measured dijkstra = measure(s.domain, s.metric, s.source, dijkstraOptions(), repeats);
  const test::RelativeErrors de = s.errorsOf(dijkstra.result);
  row("options", "curved", s.maxAnisotropy, s.domain, "Dijkstra", 1, &de, dijkstra, farErrorsOf(s, dijkstra.result));
  for (const Variant& v : variants) {
    PropagationOptions o;
    o.k = v.k;
    o.anyAngleAncestors = v.ancestors;
    if (v.reach > 0) o.segmentReach = v.reach;
    const Measured m = measure(s.domain, s.metric, s.source, o, repeats);
    const test::RelativeErrors e = s.errorsOf(m.result);
    row("options", "curved", s.maxAnisotropy, s.domain, v.name, v.k, &e, m, farErrorsOf(s, m.result));
  }
}

void bend(int n, const std::vector<double>& gammas, int repeats) {
  for (const double gamma : gammas) {
    for (const double slope : {0.1, kCurvedSlope, 0.49}) {
      const bench::Scene s = bench::pullbackScene(n, gamma, Stencil::full26(), 1, slope);
      char scene[32];
      std::snprintf(scene, sizeof scene, "curved-slope-%.2f", slope);
      const Measured m = measure(s.domain, s.metric, s.source, PropagationOptions{}, repeats);
      const test::RelativeErrors e = s.errorsOf(m.result);
      row("bend", scene, gamma, s.domain, "STVD-default", kDefaultMemoryDepth, &e, m, farErrorsOf(s, m.result));
    }
  }
}

/// The flat plane of issue 33: n x n cells over [0, 10]^2, a constant
/// metric with eigenvalues 1 and 16, the expensive axis at 30 degrees;
/// "regular": a grid with one diagonal per cell; "delaunay": the points
/// jittered by up to 0.3 cell and each cell split along the diagonal the
/// Delaunay criterion chooses.
test::GeneratedSurface anisotropicPlane(int n, bool delaunay) {
  test::GeneratedSurface s;
  test::Random random(11);
  const double h = 10.0 / n;
  auto id = [n](int i, int j) { return static_cast<VertexId>(j * (n + 1) + i); };
  for (int j = 0; j <= n; ++j)
    for (int i = 0; i <= n; ++i) {
      double x = i * h, y = j * h;
      if (delaunay && i > 0 && i < n && j > 0 && j < n) {
        x += 0.3 * h * random.uniform(-1.0, 1.0);
        y += 0.3 * h * random.uniform(-1.0, 1.0);
      }
      s.flat.push_back({x, y});
      s.points.push_back({x, y, 0.0});
    }
  // Whether d lies inside the circle through a, b, c (counter-clockwise).
  auto inCircle = [&](VertexId a, VertexId b, VertexId c, VertexId d) {
    const double ax = s.flat[a][0] - s.flat[d][0], ay = s.flat[a][1] - s.flat[d][1];
    const double bx = s.flat[b][0] - s.flat[d][0], by = s.flat[b][1] - s.flat[d][1];
    const double cx = s.flat[c][0] - s.flat[d][0], cy = s.flat[c][1] - s.flat[d][1];
    return (ax * ax + ay * ay) * (bx * cy - cx * by) - (bx * bx + by * by) * (ax * cy - cx * ay) +
               (cx * cx + cy * cy) * (ax * by - bx * ay) > 0.0;
  };
  for (int j = 0; j < n; ++j)
    for (int i = 0; i < n; ++i) {
      const VertexId a = id(i, j), b = id(i + 1, j), c = id(i + 1, j + 1), d = id(i, j + 1);
      if (!delaunay || !inCircle(a, b, c, d)) {
        s.faces.add({a, b, c});
        s.faces.add({a, c, d});
      } else {
        s.faces.add({a, b, d});
        s.faces.add({b, c, d});
      }
    }
  return s;
}

void plane(int n, int repeats) {
  std::printf("experiment\tscene\tvertices\tmethod\tparameter\tmean_rel_error\tp99_rel_error\t"
              "max_rel_error\tlonger_than_5_percent\tbelow_exact\tseconds\n");
  const auto g = test::tensor2(4.0, 30.0 * test::kPi / 180.0);
  for (bool delaunay : {false, true}) {
    const test::GeneratedSurface plane = anisotropicPlane(n, delaunay);
    const SurfaceDomain surface(plane.points, plane.faces);
    const SymTensor3 t{float(g[0]), float(g[1]), 0.f, float(g[2]), 0.f, 0.f};
    const RiemannianMetric metric =
        surfaceMetricFromWorldTensors(surface, std::vector<SymTensor3>(surface.vertexCount(), t));
    const VertexId source = test::nearestFlatVertex(plane, 5.0, 5.0);
    auto run = [&](const char* method, int k, Method m, ChainMeasure measure) {
      PropagationOptions o;
      o.method = m;
      o.k = k;
      o.chainMeasure = measure;
      std::vector<double> seconds;
      PropagationResult r;
      for (int rep = 0; rep < repeats; ++rep) {
        const auto start = std::chrono::steady_clock::now();
        r = propagate(surface, metric, {source}, o);
        seconds.push_back(std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count());
      }
      std::sort(seconds.begin(), seconds.end());
      std::vector<double> e;
      std::size_t longer = 0, below = 0;
      for (VertexId v = 0; v < surface.vertexCount(); ++v) {
        const double exact =
            test::norm2(g, plane.flat[v][0] - plane.flat[source][0], plane.flat[v][1] - plane.flat[source][1]);
        if (exact < 1e-9) continue;
        const double signedError = (r.distance[v] - exact) / exact;
        e.push_back(std::abs(signedError));
        longer += signedError > 0.05 ? 1 : 0;
        below += signedError < -1e-5 ? 1 : 0;
      }
      std::sort(e.begin(), e.end());
      double sum = 0.0;
      for (double x : e) sum += x;
      std::printf("plane\t%s\t%u\t%s\t%d\t%.6g\t%.6g\t%.6g\t%zu\t%zu\t%.6g\n", delaunay ? "delaunay" : "regular",
                  surface.vertexCount(), method, k, sum / e.size(), e[(e.size() - 1) * 99 / 100], e.back(), longer,
                  below, seconds[seconds.size() / 2]);
      std::fflush(stdout);
    };
    run("Dijkstra", 1, Method::Dijkstra, kDefaultChainMeasure);
    for (int k : {kDefaultSurfaceMemoryDepth, 16}) {
      run("STVD-segment", k, Method::ShortTermVectorDijkstra, ChainMeasure::Segment);
      run("STVD-paper", k, Method::ShortTermVectorDijkstra, ChainMeasure::ProjectionWeighted);
    }
  }
}

/// Writes a scene for scripts/hfm_comparison.py (see the top of the file).
bool phantom(const std::string& scene, int n, const std::string& prefix) {
  const bench::Scene s = namedScene(scene, n);
  const std::string nrrd = prefix + ".nrrd";
  std::FILE* f = std::fopen(nrrd.c_str(), "wb");
  if (!f) return false;
  std::fprintf(f,
               "NRRD0004\n# %s, %d^3, unit spacing: the metric tensor G per voxel\n"
               "type: float\ndimension: 4\nsizes: 6 %d %d %d\nkinds: 3D-symmetric-matrix space space space\n"
               "endian: little\nencoding: raw\nspace: left-posterior-superior\n"
               "space directions: none (1,0,0) (0,1,0) (0,0,1)\nspace origin: (0,0,0)\n"
               "measurement frame: (1,0,0) (0,1,0) (0,0,1)\n\n",
               scene.c_str(), n, n, n, n);
  std::fwrite(s.metric.params().data(), sizeof(SymTensor3), s.metric.size(), f);
  const bool tensorsWritten = std::fclose(f) == 0;
  f = std::fopen((prefix + ".exact").c_str(), "wb");
  if (!f) return false;
  std::fwrite(s.exact.data(), sizeof(double), s.exact.size(), f);
  const bool exactWritten = std::fclose(f) == 0;
  f = std::fopen((prefix + ".seed").c_str(), "w");
  if (!f) return false;
  const VoxelIndex c = s.domain.indexOf(s.source);
  std::fprintf(f, "%d %d %d\n", c.i, c.j, c.k);
  return std::fclose(f) == 0 && tensorsWritten && exactWritten;
}

void scale(int n) {
  // Exact distances are not evaluated (stride n): this run measures time
  // and memory only.
  const bench::Scene s = bench::pullbackScene(n, 20.0, Stencil::full26(), n, kCurvedSlope);
  const Measured m = measure(s.domain, s.metric, s.source, stvdOptions(kDefaultMemoryDepth), 1);
  row("scale", "curved", 20.0, s.domain, "STVD", kDefaultMemoryDepth, nullptr, m);
}

void mask(int n, int repeats) {
  const bench::Scene full = bench::pullbackScene(n, 20.0, Stencil::full26(), n, kCurvedSlope);
  const double c = 0.5 * (n - 1);
  // Ball radii holding about 100 % (no mask), 50 %, 25 % and 12.5 % of the cube.
  for (double fraction : {1.0, 0.5, 0.25, 0.125}) {
    std::vector<std::uint8_t> inside;
    if (fraction < 1.0) {
      const double radius = std::cbrt(fraction * n * n * n * 3.0 / (4.0 * test::kPi));
      inside.assign(full.domain.vertexCount(), 0);
      for (VertexId v = 0; v < full.domain.vertexCount(); ++v) {
        const VoxelIndex x = full.domain.indexOf(v);
        const double dx = x.i - c, dy = x.j - c, dz = x.k - c;
        inside[v] = dx * dx + dy * dy + dz * dz <= radius * radius ? 1 : 0;
      }
    }
    const VoxelGridDomain domain(full.domain.geometry(), Stencil::full26(), inside);
    const VertexId source = domain.vertexAt(n / 2, n / 2, n / 2);
    const Measured m = measure(domain, full.metric, source, stvdOptions(kDefaultMemoryDepth), repeats);
    row("mask", "curved", 20.0, domain, "STVD", kDefaultMemoryDepth, nullptr, m);
  }
}

/// Returns false when the runs on 1 and 2 threads differ in any bit.
bool parallel(int n, int repeats) {
  const bench::Scene s = bench::pullbackScene(n, 20.0, Stencil::full26(), n, kCurvedSlope);
  // Eight balls of radius 2 voxels spread over the box, like the regions of
  // a label image.
  std::vector<std::vector<VertexId>> sets;
  for (int b = 0; b < 8; ++b) {
    const int ci = n / 4 + (b & 1) * n / 2, cj = n / 4 + ((b >> 1) & 1) * n / 2,
              ck = n / 4 + ((b >> 2) & 1) * n / 2;
    std::vector<VertexId> set;
    for (int k = -2; k <= 2; ++k)
      for (int j = -2; j <= 2; ++j)
        for (int i = -2; i <= 2; ++i)
          if (i * i + j * j + k * k <= 4) set.push_back(s.domain.vertexAt(ci + i, cj + j, ck + k));
    sets.push_back(std::move(set));
  }
  const PropagationOptions options = stvdOptions(kDefaultMemoryDepth);
  std::vector<std::vector<double>> reference;
  for (unsigned threads : {1u, 2u}) {
    std::vector<std::vector<double>> distances(sets.size());
    std::vector<std::uint64_t> edges(sets.size());
    std::vector<double> seconds;
    for (int r = 0; r < repeats; ++r) {
      const auto start = std::chrono::steady_clock::now();
      propagateEachSourceSet(s.domain, s.metric, sets, options, threads,
                             [&](std::size_t set, PropagationResult&& result) {
                               edges[set] = result.relaxedEdges;
                               distances[set] = std::move(result.distance);
                             });
      seconds.push_back(std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count());
    }
    std::sort(seconds.begin(), seconds.end());
    Measured m;
    m.seconds = seconds[seconds.size() / 2];
    for (std::uint64_t e : edges) m.result.relaxedEdges += e;
    row("parallel", "curved", 20.0, s.domain, "STVD", static_cast<int>(threads), nullptr, m);
    if (reference.empty()) {
      reference = std::move(distances);
    } else {
      for (std::size_t set = 0; set < sets.size(); ++set)
        if (std::memcmp(reference[set].data(), distances[set].data(),
                        reference[set].size() * sizeof(double)) != 0) {
          std::fprintf(stderr, "stvd_evaluation: source set %zu differs between 1 and %u threads\n",
                       set, threads);
          return false;
        }
    }
  }
  return true;
}

std::vector<double> parseList(const char* text) {
  std::vector<double> values;
  std::stringstream in(text);
  std::string item;
  while (std::getline(in, item, ',')) values.push_back(std::atof(item.c_str()));
  return values;
}

int usage() {
  std::fprintf(stderr,
               "usage: stvd_evaluation sweep|refinement|convergence|options|bend|plane|scale|mask|parallel|phantom [--size N] "
               "[--gammas G1,G2,...] [--repeats R] [--steiner-max M] [--no-header] [--scene S --out PREFIX]\n");
  return 2;
}

}  // namespace

int main(int argc, char** argv) {
  if (argc < 2) return usage();
  const std::string experiment = argv[1];
  int n = 64, repeats = 3, steinerMax = 0;
  bool withHeader = true;
  std::string scene = "curved", out;
  std::vector<double> gammas = {1, 5, 10, 20, 50};
  for (int a = 2; a < argc; ++a) {
    const bool hasValue = a + 1 < argc;
    if (!std::strcmp(argv[a], "--size") && hasValue) n = std::atoi(argv[++a]);
    else if (!std::strcmp(argv[a], "--repeats") && hasValue) repeats = std::max(1, std::atoi(argv[++a]));
    else if (!std::strcmp(argv[a], "--gammas") && hasValue) gammas = parseList(argv[++a]);
    else if (!std::strcmp(argv[a], "--steiner-max") && hasValue) steinerMax = std::atoi(argv[++a]);
    else if (!std::strcmp(argv[a], "--no-header")) withHeader = false;
    else if (!std::strcmp(argv[a], "--scene") && hasValue) scene = argv[++a];
    else if (!std::strcmp(argv[a], "--out") && hasValue) out = argv[++a];
    else return usage();
  }
  if (n < 8 || gammas.empty() || steinerMax < 0 || steinerMax > kMaxSteinerPoints) return usage();
  if (experiment == "phantom") {
    if (out.empty()) return usage();
    if (!phantom(scene, n, out)) {
      std::fprintf(stderr, "stvd_evaluation: cannot write %s.*\n", out.c_str());
      return 1;
    }
    return 0;
  }
  if (experiment == "plane") {
    plane(n, repeats);
    return 0;
  }
  if (withHeader) header();
  if (experiment == "sweep") sweep(n, gammas, repeats, steinerMax);
  else if (experiment == "refinement") refinement(repeats);
  else if (experiment == "convergence") convergence(repeats, n);
  else if (experiment == "options") options(n, repeats);
  else if (experiment == "bend") bend(n, gammas, repeats);
  else if (experiment == "scale") scale(n);
  else if (experiment == "mask") mask(n, repeats);
  else if (experiment == "parallel") return parallel(n, repeats) ? 0 : 3;
  else return usage();
  return 0;
}
