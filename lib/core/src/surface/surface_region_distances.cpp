#include "stvd/surface/surface_region_distances.hpp"

#include <algorithm>
#include <mutex>

#include "stvd/surface/surface_propagation.hpp"
#include "stvd/system/parallel_tasks.hpp"

namespace stvd {

SurfaceRegionDistances surfaceRegionDistances(const SurfaceDomain& surface, const RiemannianMetric& metric,
                                              const ManifoldSheets& sheets,
                                              const std::vector<std::vector<VertexId>>& regions,
                                              const PropagationOptions& options, unsigned threads, bool keepMaps) {
  const std::size_t r = regions.size(), n = sheets.inputVertexCount;
  // Each region as vertices of the split mesh: all copies of its vertices.
  std::vector<std::vector<VertexId>> sources(r);
  for (std::size_t a = 0; a < r; ++a)
    for (const VertexId v : regions[a])
      for (const VertexId c : sheets.changed() ? sheets.copiesOf(v) : std::vector<VertexId>{v})
        sources[a].push_back(c);
  SurfaceRegionDistances out;
  out.matrix.assign(r * r, kUnreachable);
  out.nearestRegion.assign(n, SurfaceRegionDistances::kNoRegion);
  out.nearestDistance.assign(n, kUnreachable);
  if (keepMaps) out.maps.resize(r);
  std::mutex merge;
  forEachTaskInParallel(r, threads, [&](std::size_t a) {
    PropagationResult result = propagateOverSheets(surface, metric, sheets, sources[a], options);
    result.distance.resize(n);
    // Row a: its own cells only, no lock needed.
    for (std::size_t b = 0; b < r; ++b) {
      double d = kUnreachable;
      for (const VertexId v : regions[b]) d = std::min(d, result.distance[v]);
      out.matrix[a * r + b] = a == b ? 0.0 : d;
    }
    {
      // The nearest region: the shorter distance, then the lower index, so
      // the order in which the threads merge does not matter.
      const std::lock_guard<std::mutex> lock(merge);
      for (std::size_t v = 0; v < n; ++v) {
        const double d = result.distance[v];
        if (d < out.nearestDistance[v] || (d == out.nearestDistance[v] && d < kUnreachable && a < out.nearestRegion[v])) {
          out.nearestDistance[v] = d;
          out.nearestRegion[v] = a;
        }
      }
    }
    if (keepMaps) out.maps[a] = std::move(result.distance);
  });
  return out;
}

}  // namespace stvd
