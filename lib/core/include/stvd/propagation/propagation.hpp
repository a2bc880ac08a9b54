// Distance propagation over a domain: Dijkstra and Short-Term Vector
// Dijkstra (Campen, Heistermann, Kobbelt, "Practical Anisotropic Geodesy",
// SGP 2013, section 6).
#pragma once

#include <cstdint>
#include <functional>
#include <limits>
#include <optional>
#include <vector>

#include "stvd/metric/metric_field.hpp"
#include "stvd/propagation/domain_hooks.hpp"
#include "stvd/system/interrupter.hpp"
#include "stvd/types.hpp"

namespace stvd {

enum class Method {
  /// Shortest edge paths: each edge measured by its own norm.
  Dijkstra,
  /// Short-Term Vector Dijkstra: the update of w from v takes the minimum
  /// over i = 1..k of dist(pred_i) + l_g(e_1 + ... + e_i) along the
  /// predecessor chain w <- v <- pred(v) <- ...
  ShortTermVectorDijkstra,
};

/// How STVD measures a candidate: the path from chain vertex c_{i-1} to the
/// neighbour w that replaces the zig-zag of i chain edges. All three rules
/// agree exactly for a constant norm, and every candidate, whatever the
/// rule, is used only when its path lies in the domain (CandidatePath).
enum class ChainMeasure {
  /// The default: the candidate's own path (on a grid the straight segment
  /// c_{i-1} -> w) measured along itself, with the metric interpolated
  /// where the path runs: one sample per chain edge it replaces, at the
  /// midpoints of equal pieces (candidate_path.hpp). Candidates are first
  /// ranked by a cheap screen (SegmentScreen), and only the best one that
  /// could still win is measured. Its tensors come from along the segment,
  /// not from the chain, so the minimum over candidates cannot pick chains
  /// that wander through cheap voxels: on smooth curved metrics it is never
  /// below the exact distance, and it converges with k (docs/benchmarks.md).
  /// Domains that cannot interpolate along a path (an explicit edge graph)
  /// use LargestEdgeNorm instead.
  Segment,
  /// The paper's rule (section 6): the sum vector E = e_1 + ... + e_i is
  /// split among its edges by their signed orthogonal projections,
  /// l = max(0, sum_j (e_j . Ebar) ||Ebar||_{g_j}). On a metric whose strong
  /// direction turns from voxel to voxel (noisy tensor fields, strongly
  /// curved anisotropy) the portions of edges that point backwards cancel
  /// expensive forward portions and distances come out too short,
  /// increasingly so with larger k (docs/benchmarks.md).
  ProjectionWeighted,
  /// The earlier conservative rule: l = |E| max_j ||Ebar||_{g_j}, E
  /// measured with the most expensive of the chain's edge norms in its
  /// direction. It cannot cancel, so it does not collapse on noisy fields,
  /// but it overestimates on curved metrics and stops improving beyond
  /// k = 5 or so.
  LargestEdgeNorm,
};

/// "segment", "projection" or "largest": the names the tool and the stats use.
inline const char* chainMeasureName(ChainMeasure m) {
  return m == ChainMeasure::Segment ? "segment" : m == ChainMeasure::ProjectionWeighted ? "projection" : "largest";
}

/// How ChainMeasure::Segment ranks the candidates of a relaxation before it
/// measures one along its path. A screen only picks the candidate and sets
/// the vertex's place in the queue until it is measured; no screened value
/// becomes a distance.
enum class SegmentScreen {
  /// The segment measured with the mean of the norms of the chain's
  /// vertices c_0 .. c_{i-1} and w: one norm per candidate (the default).
  ChainMean,
  /// The paper's projection-weighted chain rule
  /// (ChainMeasure::ProjectionWeighted): i norms per candidate; ranks a
  /// little better on curved metrics, at several times the cost for large k.
  ProjectionWeighted,
};

/// Largest supported short-term memory depth k.
inline constexpr int kMaxMemoryDepth = 16;
/// Default k on volumes (voxel grids, tetrahedral and polyhedral meshes), in
/// the library and the tool alike, chosen from the accuracy/time tables in
/// docs/benchmarks.md: on curved metrics the segment measure's error falls
/// little beyond it (anisotropy 20: 1.48 % at k = 6, 1.41 % at 8), while its
/// cost grows by about a third of Dijkstra's per step of k.
inline constexpr int kDefaultMemoryDepth = 6;
/// Default k on surfaces (docs/surfaces.md): lines across badly shaped
/// triangles need longer chains (CAD mesh "cheese": 5.8 % at k = 4, 1.9 % at
/// k = 8 against exact geodesics).
inline constexpr int kDefaultSurfaceMemoryDepth = 8;
/// Default rule of the library and the tool.
inline constexpr ChainMeasure kDefaultChainMeasure = ChainMeasure::Segment;
/// Default number of any-angle ancestors (PropagationOptions::anyAngleAncestors).
inline constexpr int kDefaultAnyAngleAncestors = 1;
/// Most any-angle ancestors a relaxation may use.
inline constexpr int kMaxAnyAngleAncestors = 4;
/// Most vertices of a chain with its any-angle ancestors (and a source).
inline constexpr int kMaxChainLength = kMaxMemoryDepth + kMaxAnyAngleAncestors + 1;

/// How far the propagation has come; handed to the progress callback.
struct PropagationProgress {
  std::uint64_t finalizedVertices = 0;
  std::uint64_t domainVertices = 0;  // vertices inside the domain
  double frontDistance = 0.0;        // distance of the last finalised vertex
  /// The share of the work done, 0 in the first report, finalised / domain
  /// vertices while the front runs, exactly 1 in the last report of a run
  /// that was not cancelled (also when vertices stayed unreached).
  double fraction = 0.0;
};

struct PropagationOptions {
  Method method = Method::ShortTermVectorDijkstra;
  /// STVD memory depth, 1..kMaxMemoryDepth (k = 1 is Dijkstra exactly);
  /// unset: the domain's default (defaultMemoryDepth).
  std::optional<int> k;
  /// How STVD measures a candidate.
  ChainMeasure chainMeasure = kDefaultChainMeasure;
  /// How ChainMeasure::Segment ranks candidates before measuring one.
  SegmentScreen segmentScreen = SegmentScreen::ChainMean;
  /// ChainMeasure::Segment on voxel grids and tetrahedral meshes: how many
  /// any-angle ancestors of v are candidates of its neighbours besides its
  /// k-vertex chain (0..kMaxAnyAngleAncestors; 0 is the chain alone, STVD
  /// before issue 33). A vertex's any-angle ancestor is the vertex its
  /// distance was measured from: the start of the straight segment that gave
  /// it (its predecessor in the result), then that vertex's, and so on, so
  /// that the memory reaches a distance rather than k edges
  /// (docs/architecture.md).
  int anyAngleAncestors = kDefaultAnyAngleAncestors;
  /// How far an any-angle ancestor may lie from v, in the domain's steps
  /// (CandidatePath::steps: voxel steps on a grid, mean edge lengths on a
  /// mesh); unset: the domain's default, which grows with its resolution
  /// (CandidatePath::defaultReach).
  std::optional<int> segmentReach;
  /// The same for a source as an any-angle ancestor (source factoring: the
  /// straight segment from the seed, for the vertices whose own segment
  /// starts at the seed); unset: the domain's default.
  std::optional<int> sourceReach;
  /// Stop once the next vertex to finalise is farther than this.
  double maxDistance = std::numeric_limits<double>::infinity();
  /// When not empty: stop as soon as all these vertices are final.
  std::vector<VertexId> targets;
  /// When not empty: the distance each source starts at, one per source in
  /// the order given (by default 0). A source at distance d stands for a
  /// path of length d that ends there (the copies of a split non-manifold
  /// vertex, surface/manifold_sheets.hpp); finite and not negative.
  std::vector<double> sourceDistances;
  /// Called once at the start (fraction 0), at least about every
  /// progressInterval seconds while the front runs, and once at the end
  /// (fraction 1) unless the run was cancelled; return false to cancel.
  /// The loop looks at the clock every 1024 finalised vertices, so the
  /// calls cost nothing measurable (bench/propagation_speed).
  ///
  /// A cancelled run returns Termination::Cancelled and no distances: every
  /// vertex is kUnreachable with predecessor kNoVertex (a half-finished map
  /// cannot be mistaken for a result); the counters say how far it came.
  std::function<bool(const PropagationProgress&)> progress;
  /// The same reports for an Interrupter (system/interrupter.hpp):
  /// start("propagation"), wasInterrupted(percent), end(). Not owned.
  Interrupter* interrupter = nullptr;
  /// The longest time between two reports, seconds.
  double progressInterval = kDefaultInterruptInterval;
};

enum class Termination {
  Completed,           ///< the queue ran empty: every reachable vertex is final
  MaxDistanceReached,  ///< stopped at options.maxDistance
  TargetsReached,      ///< stopped once all targets were final
  Cancelled,           ///< the progress callback returned false
};

/// "completed", "max_distance_reached", "targets_reached" or "cancelled":
/// the names the tool's statistics and the Python package use.
inline const char* terminationName(Termination t) {
  switch (t) {
    case Termination::Completed: return "completed";
    case Termination::MaxDistanceReached: return "max_distance_reached";
    case Termination::TargetsReached: return "targets_reached";
    case Termination::Cancelled: return "cancelled";
  }
  return "?";
}

struct PropagationResult {
  /// Distance per vertex (millimetres for physical domains). kUnreachable
  /// (+infinity) for every vertex that is not final: outside the domain,
  /// disconnected from the sources, or left when the propagation stopped.
  std::vector<double> distance;
  /// Predecessor of each final vertex on its propagation path; kNoVertex for
  /// sources and for vertices that are not final.
  std::vector<VertexId> predecessor;
  /// Whether `predecessor` holds the propagation's paths. False for a
  /// Steiner-point propagation (LanthierResult), whose paths run through
  /// Steiner points and are not kept: predecessorPath, discreteGeodesicPath
  /// and traceGeodesicPath refuse such a result with std::invalid_argument.
  bool hasPredecessors = true;
  Termination termination = Termination::Completed;
  std::uint64_t finalizedVertices = 0;
  /// Distance updates evaluated: one per (finalised v, neighbour w) pair
  /// with w in the domain and not yet final.
  std::uint64_t relaxedEdges = 0;
  /// STVD candidates measured along their path (ChainMeasure::Segment).
  std::uint64_t measuredCandidates = 0;
  /// STVD candidates refused because their path leaves the domain (a
  /// masked voxel, a gap the connectivity does not join, the outside of a
  /// mesh or surface); the next best candidate was tried instead.
  std::uint64_t refusedCandidates = 0;
  /// Peak bytes of propagation state (per-vertex distance, predecessor and
  /// queue slot, the queue, and the result arrays while they are filled),
  /// excluding the domain and the metric.
  std::uint64_t peakStateBytes = 0;
};

/// The memory depth a run of `options` over a Domain uses.
template <class Domain>
int memoryDepth(const PropagationOptions& options) {
  return options.k.value_or(defaultMemoryDepth<Domain>());
}

/// Propagates distances from `sources` (distance 0) over `domain` under
/// `metric`. Throws std::invalid_argument when the metric's size differs from
/// the domain's vertex count, there is no source, a source lies outside the
/// domain, k is out of range, or a target is out of range.
template <class Domain, class Norm>
PropagationResult propagate(const Domain& domain, const MetricField<Norm>& metric,
                            const std::vector<VertexId>& sources,
                            const PropagationOptions& options = {});

/// Dijkstra's algorithm (options.method is ignored).
template <class Domain, class Norm>
PropagationResult dijkstra(const Domain& domain, const MetricField<Norm>& metric,
                           const std::vector<VertexId>& sources, PropagationOptions options = {}) {
  options.method = Method::Dijkstra;
  return propagate(domain, metric, sources, options);
}

/// Short-Term Vector Dijkstra with memory depth k.
template <class Domain, class Norm>
PropagationResult shortTermVectorDijkstra(const Domain& domain, const MetricField<Norm>& metric,
                                          const std::vector<VertexId>& sources, int k,
                                          PropagationOptions options = {}) {
  options.method = Method::ShortTermVectorDijkstra;
  options.k = k;
  return propagate(domain, metric, sources, options);
}

// Compiled once in the library for the built-in domains and norms: the
// extern templates are in each domain's propagation header
// (voxel_grid/voxel_grid_propagation.hpp, ...), the definition in
// propagation_definition.hpp.

}  // namespace stvd
