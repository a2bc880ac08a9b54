// Prints the error-versus-time table of Lanthier's Steiner-point
// propagation next to Dijkstra and STVD (docs/benchmarks.md, last section):
// for each method the mean and max relative error against the exact
// distances of the constant and pull-back metrics, seconds, relaxed edges
// (segments evaluated, for Steiner), graph points and peak propagation
// state. One run per row: the Steiner rows take seconds to minutes.
//
//   stvd_steiner_table [--size N] [--max-steiner M] [--gamma G] [--pullback-gamma G] [--slope S]
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <string>

#include "bench_scenes.hpp"
#include "steiner_table_format.hpp"
#include "stvd/lanthier/lanthier_propagation.hpp"
#include "stvd/voxel_grid/voxel_grid_lanthier.hpp"

namespace {

using namespace stvd;

void row(const bench::Scene& scene, const std::string& label, const PropagationResult& r,
         std::uint64_t points, double seconds) {
  bench::printSteinerTableRow(label, scene.errorsOf(r), r, points, seconds);
}

void table(const bench::Scene& scene, int maxSteiner) {
  std::size_t exactCount = 0;
  for (double x : scene.exact) exactCount += x > 0.0 ? 1 : 0;
  const auto& size = scene.domain.geometry().size;
  std::printf("\n#### %s, %zu^3 grid (max local anisotropy %.1f, %zu voxels with an exact distance)\n\n",
              scene.name.c_str(), size[0], scene.maxAnisotropy, exactCount);
  bench::printSteinerTableHeader();
  const std::vector<VertexId> sources{scene.source};
  PropagationResult r;
  double s = bench::timedSeconds([&] { r = dijkstra(scene.domain, scene.metric, sources); });
  row(scene, "Dijkstra, 26-neighbourhood", r, scene.domain.vertexCount(), s);
  for (int k : {5, 8}) {
    s = bench::timedSeconds([&] { r = shortTermVectorDijkstra(scene.domain, scene.metric, sources, k); });
    row(scene, "STVD k = " + std::to_string(k) + ", 26-neighbourhood", r, scene.domain.vertexCount(), s);
  }
  bench::printLanthierRows(scene.domain, scene.metric, sources, maxSteiner,
                           [&](const std::string& label, const PropagationResult& result, std::uint64_t points,
                               double seconds) { row(scene, label, result, points, seconds); });
}

}  // namespace

int main(int argc, char** argv) {
  int size = 32, maxSteiner = 8;
  double gamma = 10.0, pullbackGamma = 20.0, slope = 0.25;
  for (int a = 1; a < argc; ++a) {
    auto value = [&](const char* name) {
      if (a + 1 >= argc) {
        std::fprintf(stderr, "stvd_steiner_table: %s needs a value\n", name);
        std::exit(2);
      }
      return argv[++a];
    };
    if (!std::strcmp(argv[a], "--size")) {
      size = std::atoi(value("--size"));
    } else if (!std::strcmp(argv[a], "--max-steiner")) {
      maxSteiner = std::atoi(value("--max-steiner"));
    } else if (!std::strcmp(argv[a], "--gamma")) {
      gamma = std::atof(value("--gamma"));
    } else if (!std::strcmp(argv[a], "--pullback-gamma")) {
      pullbackGamma = std::atof(value("--pullback-gamma"));
    } else if (!std::strcmp(argv[a], "--slope")) {
      slope = std::atof(value("--slope"));
    } else {
      std::fprintf(stderr,
                   "usage: stvd_steiner_table [--size N] [--max-steiner M] [--gamma G] [--pullback-gamma G] "
                   "[--slope S]\n");
      return 2;
    }
  }
  if (size < 4 || maxSteiner < 1 || maxSteiner > kMaxSteinerPoints) {
    std::fprintf(stderr, "stvd_steiner_table: --size must be at least 4 and --max-steiner within 1..%d\n",
                 kMaxSteinerPoints);
    return 2;
  }
  std::printf("### Lanthier's Steiner points against Dijkstra and STVD\n");
  table(bench::constantScene(size, gamma, Stencil::full26()), maxSteiner);
  table(bench::pullbackScene(size, pullbackGamma, Stencil::full26(), 1, slope), maxSteiner);
  return 0;
}
