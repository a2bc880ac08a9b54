// Distance propagation over a domain: Dijkstra and Short-Term Vector
// Dijkstra (Campen, Heistermann, Kobbelt, "Practical Anisotropic Geodesy",
// SGP 2013, section 6).
#pragma once

#include <cstdint>
#include <functional>
#include <limits>
#include <vector>

#include "stvd/cell_mesh_domain.hpp"
#include "stvd/metric_field.hpp"
#include "stvd/types.hpp"
#include "stvd/voxel_grid_domain.hpp"

namespace stvd {

enum class Method {
  /// Shortest edge paths: each edge measured by its own norm.
  Dijkstra,
  /// Short-Term Vector Dijkstra: the update of w from v takes the minimum
  /// over i = 1..k of dist(pred_i) + l_g(e_1 + ... + e_i) along the
  /// predecessor chain w <- v <- pred(v) <- ...
  ShortTermVectorDijkstra,
};

/// How STVD measures a sum vector E = e_1 + ... + e_i of chain edges whose
/// norms differ (the two rules agree exactly for a constant norm).
enum class ChainMeasure {
  /// The paper's rule (section 6): E is split among its edges by their signed
  /// orthogonal projections, l = max(0, sum_j (e_j . Ebar) ||Ebar||_{g_j}).
  /// On a metric whose strong direction turns from voxel to voxel (noisy
  /// tensor fields, strongly curved anisotropy) the portions of edges that
  /// point backwards cancel expensive forward portions and distances come
  /// out too short, increasingly so with larger k (docs/benchmarks.md).
  ProjectionWeighted,
  /// l = |E| max_j ||Ebar||_{g_j}: E measured with the most expensive of the
  /// chain's edge norms in its direction. It cannot cancel, so it does not
  /// collapse on noisy fields; on smooth curved metrics it overestimates a
  /// little where the paper's rule underestimates.
  LargestEdgeNorm,
};

/// Largest supported short-term memory depth k.
inline constexpr int kMaxMemoryDepth = 16;
/// Default k, chosen from the accuracy/time tables in docs/benchmarks.md:
/// on a 26-neighbourhood it costs about 2.5 times Dijkstra, and on curved
/// anisotropic metrics larger k gains nothing (longer vector sums start to
/// underestimate), while a constant metric keeps improving up to k = 16.
inline constexpr int kDefaultMemoryDepth = 5;

/// How far the propagation has come; handed to the progress callback.
struct PropagationProgress {
  std::uint64_t finalizedVertices = 0;
  std::uint64_t domainVertices = 0;  // vertices inside the domain
  double frontDistance = 0.0;        // distance of the last finalised vertex
};

struct PropagationOptions {
  Method method = Method::ShortTermVectorDijkstra;
  /// STVD memory depth, 1..kMaxMemoryDepth. k = 1 is Dijkstra exactly.
  int k = kDefaultMemoryDepth;
  /// STVD rule for measuring a sum of chain edges.
  ChainMeasure chainMeasure = ChainMeasure::ProjectionWeighted;
  /// Stop once the next vertex to finalise is farther than this.
  double maxDistance = std::numeric_limits<double>::infinity();
  /// When not empty: stop as soon as all these vertices are final.
  std::vector<VertexId> targets;
  /// Called about every 65536 finalised vertices; return false to cancel.
  std::function<bool(const PropagationProgress&)> progress;
};

enum class Termination {
  Completed,           ///< the queue ran empty: every reachable vertex is final
  MaxDistanceReached,  ///< stopped at options.maxDistance
  TargetsReached,      ///< stopped once all targets were final
  Cancelled,           ///< the progress callback returned false
};

struct PropagationResult {
  /// Distance per vertex (millimetres for physical domains). kUnreachable
  /// (+infinity) for every vertex that is not final: outside the domain,
  /// disconnected from the sources, or left when the propagation stopped.
  std::vector<double> distance;
  /// Predecessor of each final vertex on its propagation path; kNoVertex for
  /// sources and for vertices that are not final.
  std::vector<VertexId> predecessor;
  Termination termination = Termination::Completed;
  std::uint64_t finalizedVertices = 0;
  /// Distance updates evaluated: one per (finalised v, neighbour w) pair
  /// with w in the domain and not yet final.
  std::uint64_t relaxedEdges = 0;
  /// Peak bytes of propagation state (per-vertex distance, predecessor and
  /// queue slot, the queue, and the result arrays while they are filled),
  /// excluding the domain and the metric.
  std::uint64_t peakStateBytes = 0;
};

/// An upper estimate of the memory propagate() allocates over `vertexCount`
/// vertex slots of which `domainVertexCount` are in the domain (the domain
/// and the metric not included): the 16-byte record per slot, the queue
/// (allowed 64 bytes per domain vertex plus 1 MiB; on the sample brain it
/// peaked at 43 to 58 bytes per domain voxel with the 26- to 290-neighbour
/// stencils, stale entries and partly filled 4 KiB chunks included) and the
/// result's 12 bytes per slot. For checking a run against the memory
/// available before it starts (stvd/system_memory.hpp).
std::uint64_t propagationMemoryEstimate(std::uint64_t vertexCount, std::uint64_t domainVertexCount);

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

// Compiled once in the library for the built-in domains and norms.
extern template PropagationResult propagate(const VoxelGridDomain&, const RiemannianMetric&,
                                            const std::vector<VertexId>&,
                                            const PropagationOptions&);
extern template PropagationResult propagate(const VoxelGridDomain&, const RandersMetric&,
                                            const std::vector<VertexId>&,
                                            const PropagationOptions&);
extern template PropagationResult propagate(const CellMeshDomain&, const RiemannianMetric&,
                                            const std::vector<VertexId>&,
                                            const PropagationOptions&);
extern template PropagationResult propagate(const CellMeshDomain&, const RandersMetric&,
                                            const std::vector<VertexId>&,
                                            const PropagationOptions&);

}  // namespace stvd
