// Per-vertex values of a tetrahedral mesh resampled onto a voxel grid, by
// linear (barycentric) interpolation inside the tetrahedron that contains
// each voxel centre.
#pragma once

#include <vector>

#include "stvd/tetmesh/tet_mesh.hpp"
#include "stvd/voxel_grid/grid_geometry.hpp"

namespace stvd::tetmesh {

/// How the mesh's coordinates relate to the grid's physical (LPS) frame.
enum class MeshFrame {
  Lps,  ///< mesh coordinates are the grid's physical coordinates
  Ras,  ///< mesh (x, y, z) is LPS (-x, -y, z)
};

/// One value per voxel of `grid` (linear order i + nx (j + ny k)): the
/// barycentric interpolation of `vertexValues` in the tetrahedron that
/// contains the voxel centre (boundary included). Voxels whose centre lies in
/// no tetrahedron, or in one with a non-finite corner value (unreachable),
/// get `outsideValue`. Each tetrahedron visits only the voxels of its
/// bounding box. Throws std::invalid_argument when vertexValues has the
/// wrong size.
std::vector<double> resampleOntoGrid(const TetMesh& mesh, const std::vector<double>& vertexValues,
                                     const GridGeometry& grid, MeshFrame frame, double outsideValue);

}  // namespace stvd::tetmesh
