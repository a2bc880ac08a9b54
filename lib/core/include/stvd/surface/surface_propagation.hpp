// How a surface plugs into the propagation (propagation/domain_hooks.hpp):
// its predecessor chains are unfolded into tangent frames
// (surface_chain_unfolding.hpp), its STVD candidates are straight lines
// across the faces, used only where they exist on the surface and measured
// face by face (surface_candidate_path.hpp), its default k is
// kDefaultSurfaceMemoryDepth; and the propagation compiled in the library
// for world tensors per vertex (RiemannianNorm).
#pragma once

#include <vector>

#include "stvd/metric/metric_field.hpp"
#include "stvd/propagation/domain_hooks.hpp"
#include "stvd/propagation/propagation.hpp"
#include "stvd/surface/surface_candidate_path.hpp"
#include "stvd/surface/surface_chain_unfolding.hpp"
#include "stvd/surface/surface_domain.hpp"

namespace stvd {

template <>
struct DomainHooks<SurfaceDomain> {
  /// Surfaces are measured with RiemannianNorm only (world tensors per vertex).
  template <class Norm>
  using CandidatePath = SurfaceCandidatePath;
  using ChainUnfolding = SurfaceChainUnfolding;
  static constexpr int kDefaultMemoryDepth = kDefaultSurfaceMemoryDepth;
  /// Not tried: measuring a surface's edges also reads the end points'
  /// positions and normals.
  static constexpr bool kPrefetchesNeighborhood = false;
  static constexpr bool kChainContinuesAlongStep = false;
};

// Compiled once in the library (surface_propagation.cpp).
extern template PropagationResult propagate(const SurfaceDomain&, const RiemannianMetric&,
                                            const std::vector<VertexId>&, const PropagationOptions&);

}  // namespace stvd
