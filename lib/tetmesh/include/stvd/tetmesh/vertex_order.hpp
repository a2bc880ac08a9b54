// A cache-friendly vertex numbering for propagation. Mesh generators such as
// TetGen number vertices in insertion order, so the neighbours of a vertex
// lie far apart in memory and the propagation waits on cache misses.
// Numbering the vertices along a Morton (Z-order) curve keeps vertices that
// are close in space close in memory.
#pragma once

#include <array>
#include <vector>

#include "stvd/types.hpp"

namespace stvd::tetmesh {

struct VertexPermutation {
  std::vector<VertexId> newToOld;  ///< newToOld[n] = the old index of new vertex n
  std::vector<VertexId> oldToNew;  ///< its inverse
};

/// The vertices sorted by the Morton code of their coordinates quantised to
/// 2^21 steps over the bounding box (ties keep their old order).
VertexPermutation mortonOrder(const std::vector<Vec3d>& points);

/// Points and tetrahedra renumbered by the permutation.
std::vector<Vec3d> permutedPoints(const std::vector<Vec3d>& points, const VertexPermutation& p);
std::vector<std::array<VertexId, 4>> permutedTets(const std::vector<std::array<VertexId, 4>>& tets,
                                                  const VertexPermutation& p);

}  // namespace stvd::tetmesh
