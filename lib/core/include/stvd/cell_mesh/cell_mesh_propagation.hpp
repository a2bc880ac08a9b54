// How a cell mesh plugs into the propagation (propagation/domain_hooks.hpp):
// on a mesh built from tetrahedra its STVD candidates are straight segments
// walked through the tetrahedra, refused where they leave the mesh and
// measured with the metric interpolated along them
// (cell_mesh_candidate_path.hpp); a mesh of other cells or of edges is a
// graph only. Chains are summed in 3D; the propagation is compiled in the
// library for both built-in norms.
#pragma once

#include <vector>

#include "stvd/cell_mesh/cell_mesh_candidate_path.hpp"
#include "stvd/cell_mesh/cell_mesh_domain.hpp"
#include "stvd/metric/metric_field.hpp"
#include "stvd/propagation/chain_unfolding.hpp"
#include "stvd/propagation/domain_hooks.hpp"
#include "stvd/propagation/propagation.hpp"

namespace stvd {

template <>
struct DomainHooks<CellMeshDomain> {
  template <class Norm>
  using CandidatePath = CellMeshCandidatePath<Norm>;
  using ChainUnfolding = VolumeChainUnfolding<CellMeshDomain>;
  static constexpr int kDefaultMemoryDepth = stvd::kDefaultMemoryDepth;
  /// Neighbours are single vertices of the adjacency list (forEachNeighborRun).
  static constexpr bool kPrefetchesNeighborhood = true;
  /// Vertex numbers say nothing about where a chain goes on.
  static constexpr bool kChainContinuesAlongStep = false;
};

// Compiled once in the library (cell_mesh_propagation.cpp).
extern template PropagationResult propagate(const CellMeshDomain&, const RiemannianMetric&,
                                            const std::vector<VertexId>&, const PropagationOptions&);
extern template PropagationResult propagate(const CellMeshDomain&, const RandersMetric&,
                                            const std::vector<VertexId>&, const PropagationOptions&);

}  // namespace stvd
