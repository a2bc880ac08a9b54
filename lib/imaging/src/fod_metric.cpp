#include "stvd/imaging/fod_metric.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

#include "stvd/propagation/propagation_definition.hpp"
#include "stvd/system/parallel_tasks.hpp"
#include "stvd/voxel_grid/voxel_grid_propagation.hpp"

namespace stvd::imaging {

float FodStencilNorm::offStencilLength(const EdgeParams& g, float x, float y, float z) {
  // The neighbour vectors from the index offsets: invert toIndex.
  const float* m = g.toIndex;
  const double det = m[0] * (double(m[4]) * m[8] - double(m[5]) * m[7]) -
                     m[1] * (double(m[3]) * m[8] - double(m[5]) * m[6]) +
                     m[2] * (double(m[3]) * m[7] - double(m[4]) * m[6]);
  const double inv[9] = {(double(m[4]) * m[8] - double(m[5]) * m[7]) / det,
                         (double(m[2]) * m[7] - double(m[1]) * m[8]) / det,
                         (double(m[1]) * m[5] - double(m[2]) * m[4]) / det,
                         (double(m[5]) * m[6] - double(m[3]) * m[8]) / det,
                         (double(m[0]) * m[8] - double(m[2]) * m[6]) / det,
                         (double(m[2]) * m[3] - double(m[0]) * m[5]) / det,
                         (double(m[3]) * m[7] - double(m[4]) * m[6]) / det,
                         (double(m[1]) * m[6] - double(m[0]) * m[7]) / det,
                         (double(m[0]) * m[4] - double(m[1]) * m[3]) / det};
  Vec3d w[26];
  int q = 0;
  for (int k = -1; k <= 1; ++k)
    for (int j = -1; j <= 1; ++j)
      for (int i = -1; i <= 1; ++i) {
        if (!i && !j && !k) continue;
        const Vec3d s{inv[0] * i + inv[1] * j + inv[2] * k, inv[3] * i + inv[4] * j + inv[5] * k,
                      inv[6] * i + inv[7] * j + inv[8] * k};
        w[q] = (1.0 / (norm(s) * g.cost[q])) * s;
        ++q;
      }
  return static_cast<float>(convexHullGauge(w, 26, Vec3d{x, y, z}));
}

std::string FodStencilNorm::invalidReason(const VertexParams& p) {
  for (float c : p.cost)
    if (!(c > 0.f) || !std::isfinite(c)) return "a cost along a neighbour direction is not a positive finite number";
  for (float t : p.toIndex)
    if (!std::isfinite(t)) return "the grid's index transform is not finite";
  return {};
}

FodStencilMetric fodStencilMetric(const FodCostSampler& sampler, const std::vector<std::uint8_t>* inDomain,
                                  unsigned threads) {
  const GridGeometry& g = sampler.field().geometry;
  const std::size_t n = g.voxelCount();
  if (inDomain && inDomain->size() != n)
    throw std::invalid_argument("FOD metric: the domain mask has " + std::to_string(inDomain->size()) +
                                " voxels, the FOD " + std::to_string(n));
  // (D diag(spacing))^-1 = diag(1/spacing) D^T: D is orthonormal.
  float toIndex[9];
  for (int r = 0; r < 3; ++r)
    for (int c = 0; c < 3; ++c) toIndex[3 * r + c] = static_cast<float>(g.direction[3 * c + r] / g.spacing[r]);
  const std::vector<Vec3d> queries = neighbourDirections26(g);
  const float floorCost = static_cast<float>(1.0 / std::pow(sampler.options().floor, sampler.options().power));
  std::vector<FodStencilNorm::VertexParams> params(n);
  // Each voxel's table depends on that voxel alone, so blocks of voxels
  // run on any thread and the result is the same for every thread count.
  const std::size_t blockSize = kFodMetricBlockVoxels, blocks = (n + blockSize - 1) / blockSize;
  forEachTaskInParallel(blocks, threads, [&](std::size_t block) {
    FodUnitBall ball;
    const std::size_t end = std::min(n, (block + 1) * blockSize);
    for (std::size_t v = block * blockSize; v < end; ++v) {
      FodStencilNorm::VertexParams& p = params[v];
      std::copy(toIndex, toIndex + 9, p.toIndex);
      if (inDomain && !(*inDomain)[v]) {
        std::fill(p.cost, p.cost + 26, floorCost);
        continue;
      }
      sampler.unitBall(v, ball);
      for (int q = 0; q < 26; ++q)
        p.cost[q] = q >= 13 ? p.cost[25 - q]  // the opposite direction: F* is symmetric
                            : static_cast<float>(convexHullGauge(ball.points.data(), ball.points.size(), queries[q]));
    }
  });
  return FodStencilMetric(std::move(params), inDomain);
}

std::vector<float> convexifiedFodTable(const FodCostSampler& sampler, const std::vector<Vec3d>& queries,
                                       const std::vector<std::uint8_t>* inDomain, unsigned threads) {
  const std::size_t n = sampler.voxelCount(), q = queries.size();
  if (inDomain && inDomain->size() != n)
    throw std::invalid_argument("FOD table: the domain mask has " + std::to_string(inDomain->size()) +
                                " voxels, the FOD " + std::to_string(n));
  std::vector<std::size_t> opposite(q, q);
  for (std::size_t a = 0; a < q; ++a)
    for (std::size_t b = 0; b < a && opposite[a] == q; ++b)
      if (queries[b].x == -queries[a].x && queries[b].y == -queries[a].y && queries[b].z == -queries[a].z)
        opposite[a] = b;
  const double floorCost = 1.0 / std::pow(sampler.options().floor, sampler.options().power);
  std::vector<float> out(n * q);
  const std::size_t blockSize = kFodMetricBlockVoxels, blocks = (n + blockSize - 1) / blockSize;
  forEachTaskInParallel(blocks, threads, [&](std::size_t block) {
    FodUnitBall ball;
    const std::size_t end = std::min(n, (block + 1) * blockSize);
    for (std::size_t v = block * blockSize; v < end; ++v) {
      float* row = out.data() + v * q;
      if (inDomain && !(*inDomain)[v]) {
        for (std::size_t k = 0; k < q; ++k) row[k] = static_cast<float>(floorCost * norm(queries[k]));
        continue;
      }
      sampler.unitBall(v, ball);
      for (std::size_t k = 0; k < q; ++k)
        row[k] = opposite[k] < k ? row[opposite[k]]
                                 : static_cast<float>(convexHullGauge(ball.points.data(), ball.points.size(), queries[k]));
    }
  });
  return out;
}

}  // namespace stvd::imaging

namespace stvd {
template PropagationResult propagate(const VoxelGridDomain&, const imaging::FodStencilMetric&,
                                     const std::vector<VertexId>&, const PropagationOptions&);
}  // namespace stvd
