// How a domain plugs into the propagation: one specialisation of
// DomainHooks<Domain>, in the domain's own propagation header
// (voxel_grid/voxel_grid_propagation.hpp, cell_mesh/cell_mesh_propagation.hpp,
// surface/surface_propagation.hpp), beside the extern templates of the
// instantiations the library compiles for it. The generic propagation knows
// no concrete domain: it asks DomainHooks<Domain> for everything in which
// domains differ, and a domain that has no specialisation where the
// propagation is instantiated does not compile. There is deliberately no
// default that would accept every STVD candidate: whether a candidate's
// path lies in the domain is what keeps every distance the length of a real
// path (docs/architecture.md).
#pragma once

namespace stvd {

namespace detail {
template <class>
inline constexpr bool kHasNoDomainHooks = false;
}  // namespace detail

/// What the propagation needs of a domain beyond its graph interface
/// (vertexCount, domainVertexCount, contains, forEachNeighbor,
/// displacement, physicalPoint; docs/architecture.md). A specialisation
/// defines:
///
///   `template <class Norm> using CandidatePath = ...;`
///       whether the path an STVD candidate stands for lies in the domain,
///       and its length (the interface: propagation/candidate_path.hpp);
///   using ChainUnfolding = ...;
///       how a predecessor chain becomes vectors in one frame
///       (propagation/chain_unfolding.hpp; VolumeChainUnfolding<Domain>
///       for every domain in R^3);
///   static constexpr int kDefaultMemoryDepth = ...;
///       the k a propagation runs with when the options leave it unset;
///   static constexpr bool kPrefetchesNeighborhood = ...;
///       true when the domain offers forEachNeighborRun(v, f(first, last))
///       and prefetchNeighborGeometry(v): the propagation then asks for the
///       next vertex's neighbourhood while it relaxes the current one;
///   static constexpr bool kChainContinuesAlongStep = ...;
///       true when a predecessor chain tends to go on by the offset of its
///       last link (a grid's numbering, where the front is straight): STVD
///       then asks for the next chain's guessed vertices ahead of time.
///
/// The primary template only says that a domain has none.
template <class Domain>
struct DomainHooks {
  static_assert(detail::kHasNoDomainHooks<Domain>,
                "no DomainHooks<Domain>: include the domain's propagation header "
                "(stvd/<domain>/<domain>_propagation.hpp) or, for a domain of your own, specialise "
                "DomainHooks (stvd/propagation/domain_hooks.hpp)");
};

/// The candidate paths of STVD on a Domain measured with a Norm.
template <class Domain, class Norm>
using CandidatePath = typename DomainHooks<Domain>::template CandidatePath<Norm>;

/// How a Domain places a predecessor chain in one frame.
template <class Domain>
using ChainUnfolding = typename DomainHooks<Domain>::ChainUnfolding;

/// The default k of a domain: kDefaultMemoryDepth on volumes,
/// kDefaultSurfaceMemoryDepth on surfaces (propagation.hpp).
template <class Domain>
constexpr int defaultMemoryDepth() {
  return DomainHooks<Domain>::kDefaultMemoryDepth;
}

}  // namespace stvd
