// A voxel metric sampled at arbitrary physical points (the vertices of a
// tetrahedral mesh): log-Euclidean trilinear interpolation.
//
// The tensors of the eight voxel centres around a point are averaged with
// trilinear weights in the matrix-logarithm domain and mapped back with the
// matrix exponential, G(p) = exp(sum_i w_i log G_i) (Arsigny, Fillard,
// Pennec, Ayache 2006). The result is symmetric positive-definite whenever
// the G_i are, its determinant is the weighted geometric mean of theirs (no
// swelling of the determinant, unlike componentwise interpolation), and it
// reproduces a constant field exactly.
#pragma once

#include <cstdint>
#include <vector>

#include "stvd/types.hpp"
#include "stvd/voxel_grid/grid_geometry.hpp"

namespace stvd::imaging {

struct SampledMetric {
  /// One tensor per point: the interpolated metric, or the identity where
  /// the point is not in the domain.
  std::vector<SymTensor3> metric;
  /// 1 where the point is in the domain: inside the image and at least one
  /// of its interpolation corners with a positive weight is in the domain.
  std::vector<std::uint8_t> inDomain;
  /// Indices of the points outside the image: farther than half a voxel
  /// beyond the outermost voxel centres (the image's extent).
  std::vector<std::size_t> outsideImage;
};

/// Samples `voxelMetric` (one SPD tensor per voxel of `geometry`, in the LPS
/// frame, as imaging::buildMetric makes it) at `pointsLps`. Corners outside
/// the domain (`voxelInDomain` 0) are left out and the remaining weights
/// renormalised. Points within half a voxel outside the voxel-centre box
/// take the values of the nearest face of that box. Throws
/// std::invalid_argument when the sizes do not match.
SampledMetric sampleMetricLogEuclidean(const GridGeometry& geometry, const std::vector<SymTensor3>& voxelMetric,
                                       const std::vector<std::uint8_t>& voxelInDomain,
                                       const std::vector<Vec3d>& pointsLps);

}  // namespace stvd::imaging
