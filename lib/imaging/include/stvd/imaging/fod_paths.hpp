// Geodesic paths and region connectivity under the convexified FOD norm F*
// (fod_metric.hpp; docs/fod.md, "Paths and connectivity").
//
// A path is the propagation's predecessor chain: with Dijkstra over the
// 26-neighbour stencil every step is a neighbour step measured by F* along
// its tabulated direction, so the polyline of voxel centres has exactly the
// reported geodesic length as its F*-length (fodPathLength), and that
// length is the F-length of a path that exists. The tensor paths' gradient
// descent and refinement (path_tracing.hpp) minimise a Riemannian energy:
// under F* they would report a polyline whose F*-length is not the
// geodesic length, so FOD paths are not traced or refined.
#pragma once

#include <cstdint>
#include <vector>

#include "stvd/imaging/fod_metric.hpp"
#include "stvd/propagation/propagation.hpp"
#include "stvd/types.hpp"
#include "stvd/voxel_grid/path_tracing.hpp"
#include "stvd/voxel_grid/region_connectivity.hpp"
#include "stvd/voxel_grid/voxel_grid_domain.hpp"

namespace stvd::imaging {

/// The F*-length of the polyline through the centres of `path`'s voxels:
/// each step measured as the propagation measures an edge (the norm of
/// the mean of its two end voxels' tables along the step's direction).
double fodPathLength(const VoxelGridDomain& domain, const FodStencilMetric& metric, const std::vector<VertexId>& path);

/// The discrete path of `target` (discreteGeodesicPath) with its F*-length
/// as metricLength: equal to geodesicLength up to the rounding of single
/// precision steps.
TracedPath fodGeodesicPath(const VoxelGridDomain& domain, const FodStencilMetric& metric,
                           const PropagationResult& result, VertexId target);

/// regionConnectivity (region_connectivity.hpp) under F*, with the paths of
/// fodGeodesicPath: the same threading, progress and cancellation.
RegionConnectivity fodRegionConnectivity(const VoxelGridDomain& domain, const FodStencilMetric& metric,
                                         const std::vector<std::vector<VertexId>>& regionVoxels,
                                         const PropagationOptions& options, unsigned threads);

}  // namespace stvd::imaging
