#include "stvd/imaging/fod_metric.hpp"

#include <algorithm>
#include <atomic>
#include <cmath>
#include <cstdint>
#include <mutex>
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

namespace {

/// Runs `work(block)` for every block of kFodMetricBlockVoxels voxels on
/// `threads` threads. Each voxel's table depends on that voxel alone, so the
/// result is the same for every thread count. Progress is counted in blocks
/// done and reported by one thread at a time (the others go on computing
/// rather than wait for the report); a stop throws Cancelled and no further
/// block starts.
template <class Work>
void forEachFodTableBlock(std::size_t voxels, unsigned threads, Interrupter* interrupter, double progressInterval,
                          const Work& work) {
  const std::size_t blocks = (voxels + kFodMetricBlockVoxels - 1) / kFodMetricBlockVoxels;
  InterruptScope scope(interrupter, "FOD table", blocks, progressInterval);
  std::mutex reportMutex;
  std::atomic<std::uint64_t> blocksDone{0};
  bool stopped = false;  // under reportMutex
  forEachTaskInParallel(blocks, threads, [&](std::size_t block) {
    work(block * kFodMetricBlockVoxels, std::min(voxels, (block + 1) * kFodMetricBlockVoxels));
    const std::uint64_t done = blocksDone.fetch_add(1, std::memory_order_relaxed) + 1;
    if (interrupter) {
      std::unique_lock<std::mutex> lock(reportMutex, std::try_to_lock);
      if (lock.owns_lock() && !stopped) {
        try {
          scope.check(done);
        } catch (const Cancelled&) {
          stopped = true;  // no other thread asks again; no further block starts
          throw;
        }
      }
    }
  });
  scope.finish();
}

void checkDomainSize(const std::vector<std::uint8_t>* inDomain, std::size_t voxels, const char* what) {
  if (inDomain && inDomain->size() != voxels)
    throw std::invalid_argument(std::string(what) + ": the domain mask has " + std::to_string(inDomain->size()) +
                                " voxels, the FOD " + std::to_string(voxels));
}

}  // namespace

FodStencilMetric fodStencilMetric(const FodCostSampler& sampler, const std::vector<std::uint8_t>* inDomain,
                                  unsigned threads, Interrupter* interrupter, double progressInterval) {
  const GridGeometry& g = sampler.field().geometry;
  const std::size_t n = g.voxelCount();
  checkDomainSize(inDomain, n, "FOD metric");
  // (D diag(spacing))^-1 = diag(1/spacing) D^T: D is orthonormal.
  float toIndex[9];
  for (int r = 0; r < 3; ++r)
    for (int c = 0; c < 3; ++c) toIndex[3 * r + c] = static_cast<float>(g.direction[3 * c + r] / g.spacing[r]);
  const std::vector<Vec3d> queries = neighbourDirections26(g);
  const float floorCost = static_cast<float>(1.0 / std::pow(sampler.options().floor, sampler.options().power));
  std::vector<FodStencilNorm::VertexParams> params(n);
  forEachFodTableBlock(n, threads, interrupter, progressInterval, [&](std::size_t begin, std::size_t end) {
    FodUnitBall ball;
    ConvexHullGauges gauge;
    for (std::size_t v = begin; v < end; ++v) {
      FodStencilNorm::VertexParams& p = params[v];
      std::copy(toIndex, toIndex + 9, p.toIndex);
      if (inDomain && !(*inDomain)[v]) {
        std::fill(p.cost, p.cost + 26, floorCost);
        continue;
      }
      sampler.unitBall(v, ball);
      gauge.reset(ball.points.data(), ball.points.size());
      for (int q = 0; q < 26; ++q)
        p.cost[q] = q >= 13 ? p.cost[25 - q]  // the opposite direction: F* is symmetric
                            : static_cast<float>(gauge(queries[q]));
    }
  });
  return FodStencilMetric(std::move(params), inDomain);
}

std::vector<float> convexifiedFodTable(const FodCostSampler& sampler, const std::vector<Vec3d>& queries,
                                       const std::vector<std::uint8_t>* inDomain, unsigned threads,
                                       Interrupter* interrupter, double progressInterval) {
  const std::size_t n = sampler.voxelCount(), q = queries.size();
  checkDomainSize(inDomain, n, "FOD table");
  std::vector<std::size_t> opposite(q, q);
  for (std::size_t a = 0; a < q; ++a)
    for (std::size_t b = 0; b < a && opposite[a] == q; ++b)
      if (queries[b].x == -queries[a].x && queries[b].y == -queries[a].y && queries[b].z == -queries[a].z)
        opposite[a] = b;
  const double floorCost = 1.0 / std::pow(sampler.options().floor, sampler.options().power);
  std::vector<float> out(n * q);
  forEachFodTableBlock(n, threads, interrupter, progressInterval, [&](std::size_t begin, std::size_t end) {
    FodUnitBall ball;
    ConvexHullGauges gauge;
    for (std::size_t v = begin; v < end; ++v) {
      float* row = out.data() + v * q;
      if (inDomain && !(*inDomain)[v]) {
        for (std::size_t k = 0; k < q; ++k) row[k] = static_cast<float>(floorCost * norm(queries[k]));
        continue;
      }
      sampler.unitBall(v, ball);
      gauge.reset(ball.points.data(), ball.points.size());
      for (std::size_t k = 0; k < q; ++k)
        row[k] = opposite[k] < k ? row[opposite[k]] : static_cast<float>(gauge(queries[k]));
    }
  });
  return out;
}

}  // namespace stvd::imaging

namespace stvd {
template PropagationResult propagate(const VoxelGridDomain&, const imaging::FodStencilMetric&,
                                     const std::vector<VertexId>&, const PropagationOptions&);
}  // namespace stvd
