// Where a domain decides whether the path an STVD candidate stands for
// exists, and how long it is: the one mechanism behind "every distance is
// the length of a path that lies in the domain" (docs/architecture.md).
// Each domain names its class in its DomainHooks (domain_hooks.hpp):
// VoxelGridCandidatePath, CellMeshCandidatePath, SurfaceCandidatePath.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <type_traits>
#include <utility>

#include "stvd/detail/compiler.hpp"
#include "stvd/metric/metric_field.hpp"
#include "stvd/propagation/domain_hooks.hpp"
#include "stvd/types.hpp"

namespace stvd {

/// Returned by CandidatePath::length for a candidate whose path leaves the
/// domain.
inline constexpr float kRefusedCandidate = std::numeric_limits<float>::infinity();

/// The path of an STVD candidate. When v is finalised with the predecessor
/// chain c_0 = v, c_1 = pred(v), ..., the candidate i of its neighbour w
/// (i = 2..count) stands for a path from c_{i-1} to w that replaces the
/// zig-zag w <- v <- ... <- c_{i-1} of i edges: in a volume the straight
/// segment between the two points, on a surface the straight line in the
/// faces between them. A candidate may be used only when that path lies in
/// the domain, and ChainMeasure::Segment measures it along the path itself.
///
/// The propagation makes one CandidatePath per run and calls beginChain()
/// once per finalised vertex, before any neighbour of it is measured.
///
/// This class is the interface, and the candidate path of a domain that
/// cannot tell: an explicit graph of edges without cells has no region
/// whose inside could be checked, and no interpolation along a segment. It
/// accepts every candidate, and measuresPaths() is false, so
/// ChainMeasure::Segment falls back to ChainMeasure::LargestEdgeNorm there,
/// the chain rule that cannot go below the admissible bound
/// (docs/architecture.md). A domain takes it only by naming it in its
/// DomainHooks; the built-in domains each have their own.
template <class Domain, class Norm>
class UncheckedCandidatePath {
 public:
  UncheckedCandidatePath(const Domain&, const MetricField<Norm>&) {}

  /// Whether length() measures along the path (ChainMeasure::Segment). A
  /// candidate path whose domain type covers domains of both kinds (a cell
  /// mesh built from tetrahedra or only from edges) also defines
  ///   static bool measuresPathsOn(const Domain&),
  /// which the propagation asks too (measuresPathsOn below).
  static constexpr bool measuresPaths() { return false; }
  /// Whether a pending candidate's length depends on the chain between its
  /// two ends (a surface's unfolding): then the propagation rebuilds the
  /// chain and calls beginChain() and length(). Otherwise it calls
  ///   float segmentLength(VertexId from, VertexId w),
  /// the length of the candidate from `from` = c_{i-1} to w, and asks the
  /// data for it ahead of time with
  ///   void prefetchSegment(VertexId from, VertexId w) const;
  /// such a path's candidates are straight segments, so the any-angle
  /// ancestors (PropagationOptions::anyAngleAncestors) use it too, and ask
  ///   int steps(VertexId a, VertexId b) const,
  /// what measuring the segment from a to b costs (one sample per step), and
  ///   int defaultReach() const, int defaultSourceReach() const,
  /// the reaches when the options leave them unset (anyAngleReach below).
  static constexpr bool usesPlacedChain() { return true; }

  /// The chain of the vertex just finalised, and its vertices placed in the
  /// common frame of ChainUnfolding<Domain> (placed[0] = 0 at v).
  void beginChain(const VertexId*, int, const Vec3f*) {}

  /// False when no candidate of the current chain can leave the domain
  /// (for example on a grid far from every excluded voxel): then none is
  /// checked.
  bool mayRefuse() const { return false; }

  /// Whether the path of candidate i of neighbour w lies in the domain.
  bool accepts(int, VertexId) { return true; }

  /// The length of the path of candidate i of neighbour w, measured along
  /// it, or kRefusedCandidate when it leaves the domain. `e` is the edge
  /// v -> w in the common frame.
  float length(int, VertexId, Vec3f) { return kRefusedCandidate; }
};

/// The default reach of an any-angle ancestor (PropagationOptions::
/// segmentReach) or of a source (sourceReach) over a domain of
/// `domainVertices` vertices, in the steps of its CandidatePath. Both grow
/// with the resolution r = domainVertices^(1/3): segments get longer, in
/// steps, as a grid is refined, so that the error falls with the
/// resolution. They are bounded because a segment costs one sample per
/// step: an ancestor up to max(6, r / 20) steps (6 up to 130^3, where most
/// of the time goes), a source up to max(8, r / 2), at most 32 and 64 steps
/// (a source only where the metric is near the source's, so that on a
/// constant metric every vertex within half the grid of a centred source
/// measures the segment from it). docs/architecture.md gives the figures
/// behind the choice.
inline int anyAngleReach(std::uint64_t domainVertices, bool source) {
  const double r = std::cbrt(static_cast<double>(domainVertices));
  const double reach = source ? r / 2.0 : r / 20.0;
  const int lowest = source ? 8 : 6, highest = source ? 64 : 32;
  return std::clamp(static_cast<int>(std::lround(reach)), lowest, highest);
}

namespace detail {
template <class Path, class Domain, class = void>
struct HasMeasuresPathsOn : std::false_type {};
template <class Path, class Domain>
struct HasMeasuresPathsOn<Path, Domain, std::void_t<decltype(Path::measuresPathsOn(std::declval<const Domain&>()))>>
    : std::true_type {};

/// CandidatePath::measuresWhileChecking(), where a path offers it: true
/// when checking the candidates' paths costs about what measuring them does
/// (a surface, where one walk along the chain finds every candidate's line),
/// so that every candidate is measured when it is screened instead of
/// deferring the best one. False for the others.
template <class Path, class = void>
struct OffersMeasuringWhileChecking : std::false_type {};
template <class Path>
struct OffersMeasuringWhileChecking<Path, std::void_t<decltype(std::declval<const Path&>().measuresWhileChecking())>>
    : std::true_type {};
template <class Path>
STVD_ALWAYS_INLINE bool measuresWhileChecking(const Path& path) {
  if constexpr (OffersMeasuringWhileChecking<Path>::value)
    return path.measuresWhileChecking();
  else
    return false;
}

/// CandidatePath::measuresLongSteps() and longStepLength(v, w), where a path
/// offers them (a voxel grid): a stencil step that spans more than one voxel
/// step (the 98- and 290-neighbourhoods) is measured along itself, as a
/// candidate's segment is, instead of with the edge rule of its two end
/// points, which ignores the voxels it passes. Every method's step from v to
/// a neighbour w then costs longStepLength(v, w) where that is not negative.
template <class Path, class = void>
struct OffersLongSteps : std::false_type {};
template <class Path>
struct OffersLongSteps<Path, std::void_t<decltype(std::declval<const Path&>().measuresLongSteps())>>
    : std::true_type {};

/// CandidatePath::offersSourceLines() and sourceLineLength(w, s), where a
/// path offers them (a surface): source factoring for a path whose
/// candidates are not segments from stored ancestors. The line from a
/// vertex w straight to a source s, where the domain holds one, measured
/// along itself; kRefusedCandidate where it has none. It does not depend on
/// the chain, so it is offered once per vertex, when the vertex is first
/// reached.
template <class Path, class = void>
struct OffersSourceLines : std::false_type {};
template <class Path>
struct OffersSourceLines<Path, std::void_t<decltype(std::declval<const Path&>().offersSourceLines())>>
    : std::true_type {};
}  // namespace detail

/// Whether CandidatePath<Domain, Norm> measures along paths on `domain`:
/// measuresPaths(), and measuresPathsOn(domain) where the candidate path
/// has it.
template <class Domain, class Norm>
bool measuresPathsOn(const Domain& domain) {
  using Path = CandidatePath<Domain, Norm>;
  if constexpr (detail::HasMeasuresPathsOn<Path, Domain>::value)
    return Path::measuresPaths() && Path::measuresPathsOn(domain);
  else
    return Path::measuresPaths();
}

}  // namespace stvd
