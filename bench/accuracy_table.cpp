// Prints the accuracy-versus-k and time tables of docs/benchmarks.md:
// mean and max relative error against the exact distances of the constant
// and pull-back metrics, relaxed edges, state bytes per voxel, and the time
// of each method as a ratio to Dijkstra measured in the same run
// (alternating runs, median of the per-pair ratios).
//
//   stvd_accuracy_table [--size N] [--repeats R] [--pullback-gamma G]
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <string>
#include <vector>

#include "bench_scenes.hpp"

namespace {

using namespace stvd;

struct Timed {
  PropagationResult result;
  double seconds = 0.0;
};

Timed run(const bench::Scene& scene, const PropagationOptions& options) {
  const auto start = std::chrono::steady_clock::now();
  Timed t{propagate(scene.domain, scene.metric, {scene.source}, options), 0.0};
  t.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return t;
}

double median(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  return v[v.size() / 2];
}

/// A table row: Dijkstra (k = 0) or STVD with memory depth k and a chain measure.
struct Row {
  int k;
  ChainMeasure measure = ChainMeasure::ProjectionWeighted;
};

PropagationOptions methodOptions(Row row) {
  PropagationOptions o;
  o.method = row.k == 0 ? Method::Dijkstra : Method::ShortTermVectorDijkstra;
  o.k = std::max(row.k, 1);
  o.chainMeasure = row.measure;
  return o;
}

std::string label(Row row) {
  if (row.k == 0) return "Dijkstra";
  return "STVD k = " + std::to_string(row.k) +
         (row.measure == ChainMeasure::LargestEdgeNorm ? ", largest norm" : "");
}

void table(const bench::Scene& scene, const std::vector<Row>& rows, int repeats) {
  std::size_t exactCount = 0;
  for (double e : scene.exact) exactCount += e > 0.0 ? 1 : 0;
  std::printf("\n### %s, %zu^3 grid, %d-neighbourhood (max local anisotropy %.1f, %zu voxels "
              "with an exact distance)\n\n",
              scene.name.c_str(), scene.domain.geometry().size[0], scene.domain.stencil().size(),
              scene.maxAnisotropy, exactCount);
  std::printf("| method | mean rel. error | max rel. error | relaxed edges | ns / relaxed edge | "
              "time / Dijkstra | state bytes / voxel |\n");
  std::printf("|---|---|---|---|---|---|---|\n");
  const PropagationOptions dijkstraOptions = methodOptions({0});
  for (Row row : rows) {
    std::vector<double> ratios, seconds;
    Timed last;
    for (int r = 0; r < repeats; ++r) {
      const double reference = run(scene, dijkstraOptions).seconds;
      last = run(scene, methodOptions(row));
      ratios.push_back(last.seconds / reference);
      seconds.push_back(last.seconds);
    }
    const test::RelativeErrors e = scene.errorsOf(last.result);
    std::printf("| %s | %.3f %% | %.1f %% | %llu | %.1f | %.2f | %.1f |\n", label(row).c_str(),
                100.0 * e.mean(), 100.0 * e.max(),
                static_cast<unsigned long long>(last.result.relaxedEdges),
                1e9 * median(seconds) / double(last.result.relaxedEdges), median(ratios),
                double(last.result.peakStateBytes) / scene.domain.vertexCount());
    std::fflush(stdout);
  }
}

}  // namespace

int main(int argc, char** argv) {
  int n = 128, repeats = 3;
  double pullbackGamma = 20.0;
  for (int a = 1; a < argc; ++a) {
    auto value = [&](const char* name) {
      if (a + 1 >= argc) {
        std::fprintf(stderr, "stvd_accuracy_table: %s needs a value\n", name);
        std::exit(2);
      }
      return std::atof(argv[++a]);
    };
    if (!std::strcmp(argv[a], "--size")) n = int(value("--size"));
    else if (!std::strcmp(argv[a], "--repeats")) repeats = std::max(1, int(value("--repeats")));
    else if (!std::strcmp(argv[a], "--pullback-gamma")) pullbackGamma = value("--pullback-gamma");
    else {
      std::fprintf(stderr, "usage: stvd_accuracy_table [--size N] [--repeats R] [--pullback-gamma G]\n");
      return 2;
    }
  }
  std::vector<Row> rows;
  for (int k : {0, 2, 3, 4, 5, 6, 8, 10, 12, 16}) rows.push_back({k});
  std::vector<Row> withLargest = rows;
  for (int k : {4, 8, 16}) withLargest.push_back({k, ChainMeasure::LargestEdgeNorm});
  std::printf("## Accuracy and time versus k (26-neighbourhood)\n");
  for (double gamma : {1.0, 10.0, 50.0}) table(bench::constantScene(n, gamma, Stencil::full26()), rows, repeats);
  for (double slope : {0.1, 0.25, 0.49})
    table(bench::pullbackScene(n, pullbackGamma, Stencil::full26(), 2, slope), withLargest, repeats);

  std::printf("\n## Stencils at the default k = %d\n", kDefaultMemoryDepth);
  const std::vector<Row> defaults = {{0}, {kDefaultMemoryDepth}};
  for (const char* name : {"6", "18", "98"}) {
    table(bench::constantScene(n, 10.0, Stencil::byName(name)), defaults, repeats);
    table(bench::pullbackScene(n, pullbackGamma, Stencil::byName(name), 2, 0.25), defaults, repeats);
  }
  return 0;
}
