#include "stvd/voxel_grid/region_connectivity.hpp"

#include "stvd/voxel_grid/region_connectivity_run.hpp"

namespace stvd {

RegionConnectivity regionConnectivity(const VoxelGridDomain& domain, const RiemannianMetric& metric,
                                      const std::vector<std::vector<VertexId>>& regionVoxels,
                                      const PropagationOptions& options, unsigned threads,
                                      const PathTracingOptions& tracing) {
  return regionConnectivityWith(domain, metric, regionVoxels, options, threads, tracing,
                                [&](const PropagationResult& result, VertexId vertex, const PathTracingOptions& paths) {
                                  return traceGeodesicPath(domain, metric, result, vertex, paths);
                                });
}

}  // namespace stvd
