// The shipped brain against Lanthier's Steiner points: how far each method
// lies from the converged reference, and whether any voxel comes out shorter
// than a path can be.
//
//   stvd_brain_comparison TENSORS --seed-voxel I,J,K [--steiner M] [--fa-threshold T]
//
// The metric is built as `stvd distance` builds it from diffusion tensors
// (G = (D/MD)^-1, eigenvalue ratio capped at 100), the domain is the grid
// with the 26-neighbourhood restricted to the voxels with a usable tensor
// (and FA >= T when given). The reference is Lanthier's method with M
// Steiner points per cube edge (8 by default). For every method, over the
// voxels that both it and the reference reach, farther than 4 mm from the
// seed: the median, 5th and 95th percentile of (d - d_ref) / d_ref, the
// voxels each reaches, and the voxels below the admissible bound
// |x - seed| / sqrt(3) (G has no eigenvalue below 1/3: D/MD has none above
// 3). One tab-separated row per method on standard output; times are wall
// seconds of the propagation alone.
#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <string>
#include <vector>

#include "stvd/imaging/tensor_metric.hpp"
#include "stvd/itk/tensor_volume_io.hpp"
#include "stvd/propagation/propagation.hpp"
#include "stvd/lanthier/lanthier_propagation.hpp"
#include "stvd/voxel_grid/voxel_grid_propagation.hpp"
#include "stvd/voxel_grid/voxel_grid_lanthier.hpp"

namespace {

using namespace stvd;

double quantile(std::vector<double> v, double q) {
  if (v.empty()) return std::nan("");
  std::sort(v.begin(), v.end());
  return v[static_cast<std::size_t>(q * static_cast<double>(v.size() - 1))];
}

struct Row {
  std::string method;
  int parameter;
  std::vector<double> distance;
  double seconds;
};

int usage() {
  std::fprintf(stderr,
               "usage: stvd_brain_comparison TENSORS --seed-voxel I,J,K [--steiner M] [--fa-threshold T]\n");
  return 2;
}

}  // namespace

int main(int argc, char** argv) {
  if (argc < 4) return usage();
  const std::string path = argv[1];
  std::array<int, 3> seed{-1, -1, -1};
  int steinerPoints = 8;
  imaging::MetricOptions metricOptions;
  for (int a = 2; a < argc; ++a) {
    if (!std::strcmp(argv[a], "--seed-voxel") && a + 1 < argc) {
      if (std::sscanf(argv[++a], "%d,%d,%d", &seed[0], &seed[1], &seed[2]) != 3) return usage();
    } else if (!std::strcmp(argv[a], "--steiner") && a + 1 < argc) {
      steinerPoints = std::atoi(argv[++a]);
    } else if (!std::strcmp(argv[a], "--fa-threshold") && a + 1 < argc) {
      metricOptions.faThreshold = std::atof(argv[++a]);
    } else {
      return usage();
    }
  }
  if (seed[0] < 0) return usage();

  const imaging::TensorReadResult read = imaging::readTensorVolume(path);
  const imaging::MetricFromTensors built = imaging::buildMetric(read.volume.tensors, {}, metricOptions);
  const GridGeometry& g = read.volume.geometry;
  const VoxelGridDomain domain(g, Stencil::full26(), built.inDomain);
  const RiemannianMetric metric(built.metric, &built.inDomain);
  const VertexId source = domain.vertexAt(seed[0], seed[1], seed[2]);

  auto timed = [](auto&& run) {
    const auto start = std::chrono::steady_clock::now();
    auto result = run();
    return std::make_pair(std::move(result.distance),
                          std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count());
  };
  std::vector<Row> rows;
  auto stvd = [&](const char* name, std::optional<int> k, ChainMeasure measure, Method method,
                  int anyAngleAncestors = kDefaultAnyAngleAncestors) {
    PropagationOptions o;
    o.method = method;
    o.k = k;
    o.chainMeasure = measure;
    o.anyAngleAncestors = anyAngleAncestors;
    auto [d, s] = timed([&] { return propagate(domain, metric, {source}, o); });
    rows.push_back({name, method == Method::Dijkstra ? 1 : memoryDepth<VoxelGridDomain>(o), std::move(d), s});
  };
  LanthierOptions steiner;
  steiner.steinerPoints = steinerPoints;
  auto [reference, referenceSeconds] = timed([&] { return lanthierPropagate(domain, metric, {source}, steiner); });
  rows.push_back({"Lanthier", steinerPoints, reference, referenceSeconds});
  // The reference's own convergence: coarser Steiner counts against it.
  for (const int coarser : {4, 6}) {
    if (coarser >= steinerPoints) continue;
    LanthierOptions coarse;
    coarse.steinerPoints = coarser;
    auto [d, s] = timed([&] { return lanthierPropagate(domain, metric, {source}, coarse); });
    rows.push_back({"Lanthier", coarser, std::move(d), s});
  }
  stvd("STVD-segment (default)", std::nullopt, kDefaultChainMeasure, Method::ShortTermVectorDijkstra);
  stvd("STVD-segment, chain alone", std::nullopt, ChainMeasure::Segment, Method::ShortTermVectorDijkstra, 0);
  stvd("STVD-segment", 8, ChainMeasure::Segment, Method::ShortTermVectorDijkstra);
  stvd("STVD-paper", 8, ChainMeasure::ProjectionWeighted, Method::ShortTermVectorDijkstra);
  stvd("STVD-largest", 8, ChainMeasure::LargestEdgeNorm, Method::ShortTermVectorDijkstra);
  stvd("Dijkstra-26", std::nullopt, kDefaultChainMeasure, Method::Dijkstra);

  const Vec3d s = domain.physicalPoint(source);
  std::printf("method\tparameter\treached\tcompared\tmedian\tp5\tp95\tbelow_bound\tseconds\tp1\tp99\n");
  for (const Row& r : rows) {
    std::vector<double> deviation;
    std::size_t reached = 0, below = 0;
    for (VertexId v = 0; v < domain.vertexCount(); ++v) {
      if (!std::isfinite(r.distance[v])) continue;
      ++reached;
      const double euclidean = norm(domain.physicalPoint(v) - s);
      below += r.distance[v] < euclidean / std::sqrt(3.0) * (1.0 - 1e-5) ? 1 : 0;
      if (std::isfinite(reference[v]) && euclidean > 4.0)
        deviation.push_back((r.distance[v] - reference[v]) / reference[v]);
    }
    std::printf("%s\t%d\t%zu\t%zu\t%.5f\t%.5f\t%.5f\t%zu\t%.3f\t%.5f\t%.5f\n", r.method.c_str(), r.parameter,
                reached, deviation.size(), quantile(deviation, 0.5), quantile(deviation, 0.05),
                quantile(deviation, 0.95), below, r.seconds, quantile(deviation, 0.01), quantile(deviation, 0.99));
    std::fflush(stdout);
  }
  return 0;
}
