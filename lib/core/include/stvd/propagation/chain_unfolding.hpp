// Where a domain decides how a predecessor chain becomes vectors in one
// common frame, the step in which STVD differs between volumes and surfaces.
// Each domain names its class in its DomainHooks (domain_hooks.hpp):
// VolumeChainUnfolding below for every domain in R^3, SurfaceChainUnfolding
// (surface/surface_chain_unfolding.hpp) for surfaces.
#pragma once

#include <type_traits>
#include <utility>

#include "stvd/metric/metric_field.hpp"
#include "stvd/propagation/propagation.hpp"
#include "stvd/types.hpp"

namespace stvd {

namespace detail {
template <class Domain, class = void>
struct HasPlaceChain : std::false_type {};
template <class Domain>
struct HasPlaceChain<Domain, std::void_t<decltype(std::declval<const Domain&>().placeChain(
                                 std::declval<const VertexId*>(), 0, std::declval<Vec3f*>()))>>
    : std::true_type {};
}  // namespace detail

/// Places the vertices of a predecessor chain c_0 = v, c_1 = pred(v), ...,
/// c_{count-1} in a common frame centred at v: P[0] = 0 and P[i] the
/// position of c_i relative to v. The edge vectors STVD sums are the
/// differences of consecutive P, and the edge vectors that the domain's
/// forEachNeighbor(v, ...) reports must be expressed in the same frame.
///
/// This class serves every domain embedded in R^3 (voxel grids,
/// tetrahedral and polyhedral meshes): the 3D edge vectors are summed
/// directly (paper, section 6.2), so P[i] = x(c_i) - x(v). A 2-manifold
/// surface domain has its own (SurfaceChainUnfolding), which unfolds the
/// chain edge by edge into v's tangent plane, preserving edge lengths and
/// relative 1-ring angles (section 6), with vectors in that plane stored as
/// (x, y, 0).
///
/// edgeNorm() gives the norm that measures the edge from -> to whose vector
/// in the common frame is `e`; the propagation asks it for every edge it
/// measures (Dijkstra's edges, edge 1 and the chain edges of STVD). In R^3
/// every edge shares the one world frame, so it is Norm::edgeParams of the
/// end points, the same expression the propagation used before the hook. A
/// surface's norms live in tangent planes and must be carried into the frame
/// the chain was unfolded into, which is why the edge vector is handed over;
/// and a surface edge is measured in its faces (the cheaper of the two), so
/// that it is never shorter than a path through a face under the face-wise
/// metric (for Dijkstra and ChainMeasure::Segment; the chain rules keep the
/// paper's per-edge norms). What such a rule needs beyond the end points'
/// norms (on a surface, a tensor per edge) is made once per propagation by
/// edgeMetric() and handed to every edgeNorm() call; in R^3 it is empty.
template <class Domain>
struct VolumeChainUnfolding {
  /// Whether edgeNorm() is Norm::edgeParams of the end points, the mean of
  /// their norms where EdgeRuleIsMean<Norm> (the end-point screen relies on
  /// both).
  static constexpr bool kEdgeNormIsMean = true;
  /// The edge v -> w as forEachNeighbor(v, ...) reports it.
  static Vec3f neighborEdge(const Domain& domain, VertexId v, VertexId w) {
    return domain.displacement(v, w);
  }
  STVD_ALWAYS_INLINE static void place(const Domain& domain, const VertexId* chain, int count, Vec3f* p) {
    if constexpr (detail::HasPlaceChain<Domain>::value) {
      domain.placeChain(chain, count, p);  // a faster equivalent of the loop below
    } else {
      p[0] = Vec3f{};
      for (int i = 1; i < count; ++i) p[i] = domain.displacement(chain[0], chain[i]);
    }
  }
  /// Nothing beyond the end points' norms.
  struct EdgeMetric {};
  template <class Norm>
  static EdgeMetric edgeMetric(const Domain&, const MetricField<Norm>&, const PropagationOptions&) {
    return {};
  }
  template <class Norm>
  STVD_ALWAYS_INLINE static typename Norm::EdgeParams edgeNorm(
      const Domain&, const EdgeMetric&, const typename Norm::VertexParams& from,
      const typename Norm::VertexParams& to, VertexId, VertexId, Vec3f) {
    return Norm::edgeParams(from, to);
  }
};

}  // namespace stvd
