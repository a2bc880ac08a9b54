// Changing the frame in which a symmetric tensor's components are given.
#pragma once

#include <array>

#include "stvd/types.hpp"
#include "stvd/voxel_grid/grid_geometry.hpp"

namespace stvd::imaging {

/// A 3x3 matrix, row-major: m[3*r + c] is row r, column c.
using Matrix3 = std::array<double, 9>;

/// M T M^T: the components of T after a change of frame whose matrix M holds
/// the old frame's axes as columns, expressed in the new frame. Computed in
/// double precision.
SymTensor3 changeTensorFrame(const SymTensor3& t, const Matrix3& m);

/// diag(-1, -1, 1): RAS <-> LPS (its own inverse).
Matrix3 rasToLps();

/// The rotation part of an image geometry: the unit direction cosines of
/// the index axes as columns (GridGeometry::direction).
Matrix3 voxelAxes(const GridGeometry& geometry);

/// a * b.
Matrix3 multiply(const Matrix3& a, const Matrix3& b);

/// The angle in degrees between the grid's index axes and the nearest
/// coordinate axes of its physical frame (0 for an unrotated grid, also when
/// axes are only permuted or flipped).
double obliquityDegrees(const GridGeometry& geometry);

}  // namespace stvd::imaging
