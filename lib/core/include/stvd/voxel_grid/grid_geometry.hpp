// Physical-space geometry of a voxel grid, in the ITK convention.
#pragma once

#include <array>
#include <cstddef>

#include "stvd/types.hpp"

namespace stvd {

/// Size and placement of a voxel grid in physical space (millimetres).
///
/// The physical point of the voxel with 0-based index (i, j, k) is
///   x = origin + direction * diag(spacing) * (i, j, k)^T,
/// the convention of ITK's image geometry: `direction` holds the unit
/// direction cosines of the three index axes as its columns (row-major
/// storage, so direction[3*r + c] is row r, column c). Which physical frame
/// the points live in (LPS for ITK, RAS for NIfTI's own header) is up to the
/// adapter that filled the geometry; the core only needs it to be one
/// orthonormal Cartesian frame.
struct GridGeometry {
  std::array<std::size_t, 3> size{1, 1, 1};
  std::array<double, 3> spacing{1.0, 1.0, 1.0};
  std::array<double, 3> origin{0.0, 0.0, 0.0};
  std::array<double, 9> direction{1, 0, 0, 0, 1, 0, 0, 0, 1};

  std::size_t voxelCount() const { return size[0] * size[1] * size[2]; }

  /// The physical displacement of an index offset: direction * diag(spacing) * d.
  Vec3d indexToPhysicalOffset(double di, double dj, double dk) const {
    const double a = spacing[0] * di, b = spacing[1] * dj, c = spacing[2] * dk;
    return {direction[0] * a + direction[1] * b + direction[2] * c,
            direction[3] * a + direction[4] * b + direction[5] * c,
            direction[6] * a + direction[7] * b + direction[8] * c};
  }
  /// The physical point of a (possibly fractional) continuous index.
  Vec3d indexToPhysicalPoint(double i, double j, double k) const {
    return Vec3d{origin[0], origin[1], origin[2]} + indexToPhysicalOffset(i, j, k);
  }
  /// The continuous index of a physical point (inverse of indexToPhysicalPoint).
  Vec3d physicalPointToIndex(Vec3d p) const;

  /// Throws std::invalid_argument when a size is 0, the voxel count does not
  /// fit a VertexId, a spacing is not a positive finite number, or the
  /// direction matrix is not orthonormal to within 1e-4.
  void validate() const;
};

}  // namespace stvd
