// How a voxel grid plugs into the propagation (propagation/domain_hooks.hpp):
// its STVD candidates are straight segments between voxel centres, kept to
// the domain's region and measured with the metric interpolated along them
// (voxel_grid_candidate_path.hpp); chains are summed in 3D; and the
// propagation compiled in the library for both built-in norms.
#pragma once

#include <vector>

#include "stvd/metric/metric_field.hpp"
#include "stvd/propagation/chain_unfolding.hpp"
#include "stvd/propagation/domain_hooks.hpp"
#include "stvd/propagation/propagation.hpp"
#include "stvd/voxel_grid/voxel_grid_candidate_path.hpp"
#include "stvd/voxel_grid/voxel_grid_domain.hpp"

namespace stvd {

template <>
struct DomainHooks<VoxelGridDomain> {
  template <class Norm>
  using CandidatePath = VoxelGridCandidatePath<Norm>;
  using ChainUnfolding = VolumeChainUnfolding<VoxelGridDomain>;
  static constexpr int kDefaultMemoryDepth = stvd::kDefaultMemoryDepth;
  /// Neighbours come in rows of the stencil's block (forEachNeighborRun).
  static constexpr bool kPrefetchesNeighborhood = true;
  /// Linear voxel numbers: a straight chain steps by one offset.
  static constexpr bool kChainContinuesAlongStep = true;
};

// Compiled once in the library (voxel_grid_propagation.cpp).
extern template PropagationResult propagate(const VoxelGridDomain&, const RiemannianMetric&,
                                            const std::vector<VertexId>&, const PropagationOptions&);
extern template PropagationResult propagate(const VoxelGridDomain&, const RandersMetric&,
                                            const std::vector<VertexId>&, const PropagationOptions&);

}  // namespace stvd
