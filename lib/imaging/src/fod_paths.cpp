#include "stvd/imaging/fod_paths.hpp"

#include "stvd/voxel_grid/region_connectivity_run.hpp"

namespace stvd::imaging {

double fodPathLength(const VoxelGridDomain& domain, const FodStencilMetric& metric, const std::vector<VertexId>& path) {
  double length = 0.0;
  for (std::size_t n = 1; n < path.size(); ++n) {
    const Vec3f d = domain.displacement(path[n - 1], path[n]);
    const FodStencilNorm::EdgeParams edge = FodStencilNorm::edgeParams(metric[path[n - 1]], metric[path[n]]);
    length += static_cast<double>(FodStencilNorm::length(edge, d.x, d.y, d.z));
  }
  return length;
}

TracedPath fodGeodesicPath(const VoxelGridDomain& domain, const FodStencilMetric& metric,
                           const PropagationResult& result, VertexId target) {
  TracedPath path = discreteGeodesicPath(domain, result, target);
  if (!path.discrete.empty()) path.metricLength = fodPathLength(domain, metric, path.discrete);
  return path;
}

RegionConnectivity fodRegionConnectivity(const VoxelGridDomain& domain, const FodStencilMetric& metric,
                                         const std::vector<std::vector<VertexId>>& regionVoxels,
                                         const PropagationOptions& options, unsigned threads) {
  return regionConnectivityWith(domain, metric, regionVoxels, options, threads, PathTracingOptions{},
                                [&](const PropagationResult& result, VertexId vertex, const PathTracingOptions&) {
                                  return fodGeodesicPath(domain, metric, result, vertex);
                                });
}

}  // namespace stvd::imaging
