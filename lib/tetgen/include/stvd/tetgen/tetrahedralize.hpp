// Quality tetrahedral meshes of closed surfaces through the TetGen library
// (Hang Si, TetGen 1.5). This module links TetGen, which is licensed under
// AGPL-3.0-or-later: it is optional (STVD_WITH_TETGEN) and nothing in the
// BSD-licensed core, the tetmesh library or the `stvd` executable links it;
// `stvd tetrahedralize` runs the separate program stvd-tetrahedralize.
//
// TetGen's own error handling does not survive in Debian's build
// (degenerate input can crash it), so every input is validated first:
// finite coordinates, polygons with at least three distinct corners and a
// non-zero area, and a closed surface (every edge shared by at least two
// polygons, after merging points with identical coordinates).
#pragma once

#include <array>
#include <cstddef>
#include <optional>
#include <string>
#include <vector>

#include "stvd/tetmesh/tet_mesh.hpp"

namespace stvd::tetgen {

/// A piecewise linear surface: points and polygons (vertex indices, 0-based).
struct SurfaceMesh {
  std::vector<Vec3d> points;
  std::vector<std::vector<VertexId>> polygons;
};

/// The smallest radius-edge bound accepted (see tetrahedralize.cpp for why:
/// below it TetGen's refinement need not end, and on a unit cube it does not).
inline constexpr double kMinimumQuality = 1.1;

struct TetrahedralizeOptions {
  /// Upper bound on the volume of every tetrahedron (TetGen -a), none when unset.
  std::optional<double> maxVolume;
  /// Radius-edge ratio bound (TetGen -q), >= kMinimumQuality; TetGen's
  /// default is 2.0. Quality refinement is always on; 1.2 to 2 are usual.
  double quality = 2.0;
  /// At most this many points added to the surface's (TetGen -S): about
  /// 1.1 KB of TetGen's memory each, and six tetrahedra. A mesh that would
  /// need more is an error (TetMeshError), before meshing when the volume
  /// bound alone asks for more, otherwise when TetGen reaches the limit.
  std::size_t maxAddedPoints = 2'000'000;
};

/// Reads a surface with TetGen's loaders: .off, .stl, .ply, .poly (a .poly
/// file may refer to a .node file next to it). Throws
/// tetmesh::TetMeshError naming the file when it cannot be read.
SurfaceMesh readSurface(const std::string& path);

/// Throws tetmesh::TetMeshError naming `source` (for messages) and the first
/// problem: no polygons, a non-finite point, an index out of range, a
/// polygon with fewer than three distinct corners or a zero area, or an
/// edge used by a single polygon (the surface is not closed).
void validateSurface(const SurfaceMesh& surface, const std::string& source);

/// Validates the surface, then tetrahedralizes its interior. The result is
/// numbered from 0, in TetGen's orientation, with its boundary faces.
/// Throws tetmesh::TetMeshError for invalid input, when TetGen fails or
/// when the mesh would need more points than options.maxAddedPoints,
/// std::invalid_argument for bad options.
tetmesh::TetMesh tetrahedralizeSurface(const SurfaceMesh& surface, const TetrahedralizeOptions& options,
                                       const std::string& source);

/// The closed surface of the box [lo, hi] as six quadrilaterals.
SurfaceMesh boxSurface(const Vec3d& lo, const Vec3d& hi);

}  // namespace stvd::tetgen
