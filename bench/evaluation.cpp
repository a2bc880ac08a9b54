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
//                   [--steiner-max M] [--no-header]
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
#include <sstream>
#include <string>
#include <vector>

#include "bench_scenes.hpp"
#include "stvd/propagation/source_set_propagation.hpp"
#include "stvd/lanthier/lanthier_propagation.hpp"
#include "stvd/voxel_grid/voxel_grid_propagation.hpp"
#include "stvd/voxel_grid/voxel_grid_lanthier.hpp"

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
              "state_bytes\tpeak_rss_bytes\n");
}

/// One row. Errors are NaN where the scene has no exact distances.
void row(const char* experiment, const char* scene, double gamma, const VoxelGridDomain& domain,
         const char* method, int parameter, const test::RelativeErrors* errors,
         const Measured& m) {
  const double nan = std::nan("");
  std::printf("%s\t%s\t%g\t%zu\t%d\t%s\t%d\t%u\t%.6g\t%.6g\t%.6g\t%llu\t%.4g\t%llu\t%llu\n",
              experiment, scene, gamma, domain.geometry().size[0], domain.stencil().size(), method,
              parameter, domain.domainVertexCount(), errors ? errors->mean() : nan,
              errors ? errors->max() : nan, m.seconds,
              static_cast<unsigned long long>(m.result.relaxedEdges),
              1e9 * m.seconds / double(std::max<std::uint64_t>(m.result.relaxedEdges, 1)),
              static_cast<unsigned long long>(m.result.peakStateBytes),
              static_cast<unsigned long long>(peakResidentBytes()));
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
        row("sweep", kind, gamma, s.domain, "Dijkstra", 0, &e, m);
        if (std::string(stencilName) != "26") continue;
        for (ChainMeasure cm : {ChainMeasure::Segment, ChainMeasure::ProjectionWeighted, ChainMeasure::LargestEdgeNorm}) {
          for (int k = 2; k <= kMaxMemoryDepth; ++k) {
            const Measured mk = measure(s.domain, s.metric, s.source, stvdOptions(k, cm), repeats);
            const test::RelativeErrors ek = s.errorsOf(mk.result);
            row("sweep", kind, gamma, s.domain, measureName(cm), k, &ek, mk);
          }
        }
        for (int m = 1; m <= steinerMax; m *= 2) {
          const Measured ms = measureSteiner(s, m);
          const test::RelativeErrors em = s.errorsOf(ms.result);
          row("sweep", kind, gamma, s.domain, "Lanthier", m, &em, ms);
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
      row("refinement", kind, gamma, s.domain, "Dijkstra", 0, &ed, d);
      const Measured m = measure(s.domain, s.metric, s.source, stvdOptions(depths[level]), repeats);
      const test::RelativeErrors e = s.errorsOf(m.result);
      row("refinement", kind, gamma, s.domain, measureName(kDefaultChainMeasure), depths[level], &e, m);
    }
  }
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
               "usage: stvd_evaluation sweep|refinement|scale|mask|parallel [--size N] "
               "[--gammas G1,G2,...] [--repeats R] [--steiner-max M] [--no-header]\n");
  return 2;
}

}  // namespace

int main(int argc, char** argv) {
  if (argc < 2) return usage();
  const std::string experiment = argv[1];
  int n = 64, repeats = 3, steinerMax = 0;
  bool withHeader = true;
  std::vector<double> gammas = {1, 5, 10, 20, 50};
  for (int a = 2; a < argc; ++a) {
    const bool hasValue = a + 1 < argc;
    if (!std::strcmp(argv[a], "--size") && hasValue) n = std::atoi(argv[++a]);
    else if (!std::strcmp(argv[a], "--repeats") && hasValue) repeats = std::max(1, std::atoi(argv[++a]));
    else if (!std::strcmp(argv[a], "--gammas") && hasValue) gammas = parseList(argv[++a]);
    else if (!std::strcmp(argv[a], "--steiner-max") && hasValue) steinerMax = std::atoi(argv[++a]);
    else if (!std::strcmp(argv[a], "--no-header")) withHeader = false;
    else return usage();
  }
  if (n < 8 || gammas.empty() || steinerMax < 0 || steinerMax > kMaxSteinerPoints) return usage();
  if (withHeader) header();
  if (experiment == "sweep") sweep(n, gammas, repeats, steinerMax);
  else if (experiment == "refinement") refinement(repeats);
  else if (experiment == "scale") scale(n);
  else if (experiment == "mask") mask(n, repeats);
  else if (experiment == "parallel") return parallel(n, repeats) ? 0 : 3;
  else return usage();
  return 0;
}
