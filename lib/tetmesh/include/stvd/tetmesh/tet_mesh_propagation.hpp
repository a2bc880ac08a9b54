// A propagation over tetrahedra as stvd's front ends run it: Dijkstra or
// STVD over the edges, or Lanthier's Steiner points through the tetrahedra,
// with the vertices renumbered along a Morton curve for speed and the result
// handed back in the caller's numbering.
#pragma once

#include <array>
#include <cstdint>
#include <functional>
#include <limits>
#include <string>
#include <vector>

#include "stvd/front_end/propagation_choice.hpp"
#include "stvd/propagation/propagation.hpp"
#include "stvd/types.hpp"

namespace stvd::tetmesh {

/// The tetrahedra whose four corners are in the domain, and the vertices
/// they cover (one byte per vertex, 1 when covered).
struct TetrahedraInDomain {
  std::vector<std::array<VertexId, 4>> tets;
  std::vector<std::uint8_t> covered;
};

/// Leaves out the tetrahedra with a corner outside the domain (`inDomain`,
/// one byte per vertex), and so the edges only they contribute. Throws
/// InputError naming `meshName` for a corner out of range, and
/// NothingToCompute naming it when no tetrahedron is left.
TetrahedraInDomain tetrahedraInDomain(const std::vector<std::array<VertexId, 4>>& tets,
                                      const std::vector<std::uint8_t>& inDomain, const std::string& meshName);

struct TetMeshPropagation {
  /// Distances and predecessors per vertex, in the numbering of `points`.
  PropagationResult result;
  /// Edges of the tetrahedra (the graph Dijkstra and STVD run on).
  std::size_t edgeCount = 0;
};

/// Propagates from `sources` over `tets` (all of whose corners are in the
/// domain: the caller leaves out tetrahedra with a corner outside it) with
/// one metric tensor per point and `inDomain` marking the points that take
/// part, as `choice` says (checkMeshPropagationChoice): STVD or Dijkstra
/// with propagationOptions(choice), or Lanthier's Steiner points when
/// choice.lanthier. Propagation runs on the vertices renumbered along a
/// Morton curve (mortonOrder), so that neighbours are close in memory (1.7
/// to 2.5 times less time per edge than TetGen's numbering on a 490k-vertex
/// mesh, docs/benchmarks.md). Throws InputError naming `meshName` for
/// tetrahedra that do not form cells (a face shared by more than two),
/// OptionError naming it when the Steiner graph is too large for 32-bit
/// point numbers, and what propagate() throws.
TetMeshPropagation propagateOverTetrahedra(const std::vector<Vec3d>& points,
                                           const std::vector<std::array<VertexId, 4>>& tets,
                                           const std::vector<SymTensor3>& metric,
                                           const std::vector<std::uint8_t>& inDomain,
                                           const std::vector<VertexId>& sources, const PropagationChoice& choice,
                                           double maxDistance, const std::string& meshName,
                                           std::function<bool(const PropagationProgress&)> progress = {});

}  // namespace stvd::tetmesh
