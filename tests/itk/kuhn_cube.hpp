// A small tetrahedral mesh for the tool's tet-mesh tests: a lattice of unit
// cubes cut into six tetrahedra each.
#pragma once

#include "stvd/tetmesh/tet_mesh.hpp"
#include "stvd/types.hpp"

namespace stvd::testing {

/// A 4 x 4 x 4 cube lattice of 1 mm cells at `origin` (mesh coordinates),
/// each cube cut into six tetrahedra around its (1,1,1) diagonal, oriented
/// as TetGen orients them (positive volume), numbered from `firstIndex`.
tetmesh::TetMesh kuhnCube(Vec3d origin, int firstIndex);

}  // namespace stvd::testing
