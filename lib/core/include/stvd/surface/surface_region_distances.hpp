// Geodesic distances between the regions of a surface parcellation (a
// FreeSurfer annotation, a GIfTI label file) and from every vertex to its
// nearest region: one propagation per region, on all cores, each exactly
// what propagateOverSheets gives for that region alone (docs/surfaces.md,
// "Region distances").
#pragma once

#include <cstddef>
#include <limits>
#include <vector>

#include "stvd/propagation/propagation.hpp"
#include "stvd/surface/manifold_sheets.hpp"
#include "stvd/surface/surface_domain.hpp"

namespace stvd {

struct SurfaceRegionDistances {
  /// R x R, row-major: row a, column b is the shortest distance from
  /// region a to a vertex of region b (0 on the diagonal; kUnreachable when
  /// no vertex of b is reached from a). Not symmetric in general: each row
  /// is its own propagation.
  std::vector<double> matrix;
  /// Per input vertex: the index (into the regions given) of the nearest
  /// region, kNoRegion when none reaches it; ties go to the lower index.
  static constexpr std::size_t kNoRegion = std::numeric_limits<std::size_t>::max();
  std::vector<std::size_t> nearestRegion;
  /// Per input vertex: the distance to that region.
  std::vector<double> nearestDistance;
  /// Per region, the whole distance map over the input vertices, when asked
  /// for (keepMaps).
  std::vector<std::vector<double>> maps;
};

/// `regions` lists each region's vertices (input vertices of `sheets`;
/// every copy of them is a source). `threads` 0: one per core. The result
/// does not depend on the thread count. Throws what propagate() throws
/// (std::invalid_argument for an empty region).
SurfaceRegionDistances surfaceRegionDistances(const SurfaceDomain& surface, const RiemannianMetric& metric,
                                              const ManifoldSheets& sheets,
                                              const std::vector<std::vector<VertexId>>& regions,
                                              const PropagationOptions& options, unsigned threads,
                                              bool keepMaps = false);

}  // namespace stvd
