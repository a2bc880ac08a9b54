#include "stvd/voxel_grid/region_connectivity.hpp"

#include "stvd/system/parallel_tasks.hpp"
#include "stvd/voxel_grid/label_regions.hpp"

namespace stvd {

RegionConnectivity regionConnectivity(const VoxelGridDomain& domain, const RiemannianMetric& metric,
                                      const std::vector<std::vector<VertexId>>& regionVoxels,
                                      const PropagationOptions& options, unsigned threads,
                                      const PathTracingOptions& tracing) {
  RegionConnectivity out;
  const std::size_t n = regionVoxels.size();
  out.regionCount = n;
  out.pairs.resize(n * n);
  out.threads = threadCountFor(threads, n);
  forEachTaskInParallel(n, out.threads, [&](std::size_t a) {
    const PropagationResult result = propagate(domain, metric, regionVoxels[a], options);
    for (std::size_t b = 0; b < n; ++b) {
      if (b == a) continue;
      const VertexId nearest = nearestReached(result.distance, regionVoxels[b]);
      if (nearest == kNoVertex) continue;
      const TracedPath path = traceGeodesicPath(domain, metric, result, nearest, tracing);
      RegionPair& r = out.pairs[a * n + b];
      r.geodesic = path.geodesicLength;
      r.pathLength = path.euclideanLength;
      r.straight = norm(path.points.back() - path.points.front());
    }
  });
  return out;
}

}  // namespace stvd
