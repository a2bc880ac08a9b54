// Geodesic distance and a connectivity index between every pair of regions
// of a voxel grid: one multi-source propagation per region, the regions
// spread over threads, and the geodesic path from the nearest voxel of each
// other region traced back (docs/paths.md, `stvd connectivity`).
#pragma once

#include <cmath>
#include <cstddef>
#include <limits>
#include <vector>

#include "stvd/metric/metric_field.hpp"
#include "stvd/propagation/propagation.hpp"
#include "stvd/voxel_grid/path_tracing.hpp"
#include "stvd/voxel_grid/voxel_grid_domain.hpp"

namespace stvd {

/// The measurements of one ordered pair of regions (A, B).
struct RegionPair {
  /// d(A, B): the smallest distance from A at a voxel of B; kUnreachable
  /// when B is not reachable from A.
  double geodesic = kUnreachable;
  /// Euclidean length of the (refined) path traced from that voxel to A,
  /// and the straight distance between its end points (NaN when unreachable).
  double pathLength = std::numeric_limits<double>::quiet_NaN();
  double straight = std::numeric_limits<double>::quiet_NaN();
  /// pathLength / geodesic, the geodesic connectivity measure of Astola,
  /// Florack and ter Haar Romeny (IPMI 2007); NaN when unreachable.
  double connectivity() const {
    return std::isfinite(geodesic) && geodesic > 0.0 ? pathLength / geodesic
                                                      : std::numeric_limits<double>::quiet_NaN();
  }
};

struct RegionConnectivity {
  std::size_t regionCount = 0;
  /// regionCount^2 pairs, row a measured from region a; the diagonal is
  /// left as it is (unreachable).
  std::vector<RegionPair> pairs;
  /// How many threads ran.
  unsigned threads = 1;
  const RegionPair& operator()(std::size_t a, std::size_t b) const { return pairs[a * regionCount + b]; }
};

/// For each region (its voxels in the domain, at least one each) one
/// propagation from all its voxels at once, with `options`, on `threads`
/// threads (0: one per core); for every other region B the nearest voxel
/// (nearestReached) and the path from it, traced with `tracing`. Row a is
/// written only by the thread that propagates from region a, so the result
/// does not depend on the number of threads. Throws what propagate() and
/// traceGeodesicPath() throw.
///
/// options.interrupter hears the run as one operation, "region
/// connectivity" (0 %, the share of pairs measured at least every
/// options.progressInterval, 100 %), with each propagation and each path
/// (when `tracing` names no interrupter of its own) as operations of their
/// own within it, from several threads at once when threads > 1. When it
/// asks to stop, or a propagation's progress callback does, the
/// propagations and paths under way end at their next report and
/// Cancelled is thrown: a table with rows missing would pass for regions
/// that do not reach each other.
RegionConnectivity regionConnectivity(const VoxelGridDomain& domain, const RiemannianMetric& metric,
                                      const std::vector<std::vector<VertexId>>& regionVoxels,
                                      const PropagationOptions& options, unsigned threads,
                                      const PathTracingOptions& tracing = {});

}  // namespace stvd
