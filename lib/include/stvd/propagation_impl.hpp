// Definition of stvd::propagate. Include this header only to instantiate the
// propagation for a domain or a norm of your own; the built-in combinations
// are compiled in the library.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <limits>
#include <stdexcept>
#include <string>
#include <type_traits>
#include <utility>

#include "stvd/chain_unfolding.hpp"
#include "stvd/detail/front_queue.hpp"
#include "stvd/large_array.hpp"
#include "stvd/propagation.hpp"

namespace stvd {
namespace detail {

/// The short-term memory of one finalised vertex v: its predecessor chain
/// c_0 = v, c_1 = pred(v), ..., c_m (m < k, shorter near a source), laid out
/// for the per-neighbour update. It is the same for every neighbour w of v,
/// so it is gathered once per finalised vertex.
///
/// Candidate i = 2..m+1 of the update of w has index L = i - 2: its sum
/// vector is E_i = e_1 + ... + e_i = x(w) - x(c_{i-1}) and its base
/// distance is dist(c_{i-1}). Chain edge j >= 2 runs from c_{j-1} to c_{j-2}
/// (the direction of propagation) and is measured with the norm of its end
/// points; edge 1 (v -> w) is supplied per neighbour.
template <class Norm>
struct ChainMemory {
  using EdgeParams = typename Norm::EdgeParams;
  int edgeCount;  // m + 1: edges 1..m+1
  float backX[kMaxMemoryDepth], backY[kMaxMemoryDepth], backZ[kMaxMemoryDepth];  // x(c_{L+1}) - x(v)
  double baseDistance[kMaxMemoryDepth];  // dist(c_{L+1})
  Vec3f edge[kMaxMemoryDepth + 1];             // e_j, j = 2..m+1
  EdgeParams edgeNorm[kMaxMemoryDepth + 1];
};

/// Up to kCapacity neighbours of one popped vertex, gathered before any of
/// them is updated. The lengths of all their edges (and, for STVD, of all
/// their chain candidates) are then computed in one branch-free pass that is
/// vectorised across neighbours, and only after it the updates, with their
/// unpredictable comparisons, run. Computing and updating neighbour by
/// neighbour let every mispredicted comparison throw away the next
/// neighbour's arithmetic already in flight, and used at most as many SIMD
/// lanes as there are candidates.
///
/// The edge norms are stored component-wise (structure of arrays), so that
/// one vector load fetches a component for eight neighbours; this asks
/// Norm::EdgeParams to be a plain struct of floats, as both built-in norms are.
template <class Norm>
struct NeighborBatch {
  static constexpr int kCapacity = 32;
  using EdgeParams = typename Norm::EdgeParams;
  static_assert(std::is_trivially_copyable_v<EdgeParams> && sizeof(EdgeParams) % sizeof(float) == 0,
                "Norm::EdgeParams must be a plain struct of floats");
  static constexpr int kParamFloats = static_cast<int>(sizeof(EdgeParams) / sizeof(float));

  /// The computing loops run over whole groups of this many neighbours (the
  /// widest SIMD register holds 8 floats), so that no scalar remainder loop
  /// runs; the padding entries measure a zero edge with a zero norm.
  static constexpr int kLaneGroup = 8;
  static_assert(kCapacity % kLaneGroup == 0, "capacity must be whole lane groups");

  int size = 0;    // neighbours in the batch
  int padded = 0;  // size rounded up to whole lane groups, after pad()
  VertexId vertex[kCapacity];
  alignas(64) float ex[kCapacity], ey[kCapacity], ez[kCapacity];  // edge 1: x(w) - x(v)
  alignas(64) float param[kParamFloats][kCapacity];                 // its norm, by component
  alignas(64) double best[kCapacity];                               // shortest candidate

  STVD_ALWAYS_INLINE void add(VertexId w, Vec3f e, const EdgeParams& g) {
    vertex[size] = w;
    ex[size] = e.x;
    ey[size] = e.y;
    ez[size] = e.z;
    float flat[kParamFloats];
    std::memcpy(flat, &g, sizeof g);
    for (int c = 0; c < kParamFloats; ++c) param[c][size] = flat[c];
    ++size;
  }
  STVD_ALWAYS_INLINE void pad() {
    padded = (size + kLaneGroup - 1) / kLaneGroup * kLaneGroup;
    for (int n = size; n < padded; ++n) {
      ex[n] = ey[n] = ez[n] = 0.f;
      for (int c = 0; c < kParamFloats; ++c) param[c][n] = 0.f;
    }
  }
  STVD_ALWAYS_INLINE EdgeParams edgeNorm(int n) const {
    return gatherEdgeNorm(n, std::make_integer_sequence<int, kParamFloats>{});
  }
  // Aggregate initialisation in declaration order (the order add() copied
  // the components in), with no loop and no copy through memory, so that the
  // loops over neighbours that call it stay innermost and vectorise.
  template <int... C>
  STVD_ALWAYS_INLINE EdgeParams gatherEdgeNorm(int n, std::integer_sequence<int, C...>) const {
    return EdgeParams{param[C][n]...};
  }

  /// best[n] = dv + l(e_n): the Dijkstra candidate (and STVD's i = 1),
  /// computed by the same code for both methods, so that STVD with k = 1
  /// matches Dijkstra bit for bit.
  STVD_ALWAYS_INLINE void setDijkstraCandidates(double dv) {
    STVD_SIMD_LOOP
    for (int n = 0; n < padded; ++n)
      best[n] = dv + static_cast<double>(Norm::length(edgeNorm(n), ex[n], ey[n], ez[n]));
  }
};

/// Lowers best[n] of every neighbour in the batch to its STVD candidates
/// i = 2..m+1, base distance dist(c_{i-1}) plus l_g(E_i) with
/// E_i = e_1 + ... + e_i (see ChainMemory), one candidate at a time and all
/// neighbours at once.
///
/// ChainMeasure::ProjectionWeighted (section 6 of the paper):
///   l_g(E) = max(0, sum_j (e_j . Ebar) ||Ebar||_{g_j}),  Ebar = E / |E|:
/// E is split among its edges by their signed projections, and each portion
/// is measured with that edge's own norm.
/// ChainMeasure::LargestEdgeNorm:
///   l_g(E) = |E| max_j ||Ebar||_{g_j}:
/// the whole of E is measured with the most expensive of the chain's norms
/// in its direction.
/// A constant norm gives exactly |E| ||Ebar|| = ||E|| with either rule.
template <ChainMeasure Measure, class Norm>
STVD_ALWAYS_INLINE void lowerToChainCandidates(const ChainMemory<Norm>& chain,
                                               NeighborBatch<Norm>& batch) {
  constexpr int kCapacity = NeighborBatch<Norm>::kCapacity;
  const int size = batch.padded;
  alignas(64) float ux[kCapacity], uy[kCapacity], uz[kCapacity], acc[kCapacity], length[kCapacity];
  for (int lane = 0; lane + 2 <= chain.edgeCount; ++lane) {
    const int i = lane + 2;  // candidate i sums edges 1..i
    const float bx = chain.backX[lane], by = chain.backY[lane], bz = chain.backZ[lane];
    STVD_SIMD_LOOP
    for (int n = 0; n < size; ++n) {
      const float ex = batch.ex[n] - bx, ey = batch.ey[n] - by, ez = batch.ez[n] - bz;
      // A zero sum vector (coincident points) gives Ebar = 0 and length 0.
      const float n2 = ex * ex + ey * ey + ez * ez;
      const float inv = 1.f / std::sqrt(std::max(n2, std::numeric_limits<float>::min()));
      length[n] = n2 * inv;
      ux[n] = ex * inv;
      uy[n] = ey * inv;
      uz[n] = ez * inv;
      // Edge 1 (v -> w) belongs to every candidate.
      const float norm1 = Norm::length(batch.edgeNorm(n), ux[n], uy[n], uz[n]);
      if constexpr (Measure == ChainMeasure::ProjectionWeighted)
        acc[n] = (batch.ex[n] * ux[n] + batch.ey[n] * uy[n] + batch.ez[n] * uz[n]) * norm1;
      else
        acc[n] = norm1;
    }
    for (int j = 2; j <= i; ++j) {
      const Vec3f ej = chain.edge[j];
      const typename Norm::EdgeParams gj = chain.edgeNorm[j];
      STVD_SIMD_LOOP
      for (int n = 0; n < size; ++n) {
        const float normJ = Norm::length(gj, ux[n], uy[n], uz[n]);
        if constexpr (Measure == ChainMeasure::ProjectionWeighted)
          acc[n] += (ej.x * ux[n] + ej.y * uy[n] + ej.z * uz[n]) * normJ;
        else
          acc[n] = std::max(acc[n], normJ);
      }
    }
    const double base = chain.baseDistance[lane];
    STVD_SIMD_LOOP
    for (int n = 0; n < size; ++n) {
      const float l = Measure == ChainMeasure::ProjectionWeighted ? std::max(acc[n], 0.f)
                                                                  : length[n] * acc[n];
      batch.best[n] = std::min(batch.best[n], base + static_cast<double>(l));
    }
  }
}

template <class Domain, class Norm>
class Propagation {
 public:
  Propagation(const Domain& domain, const MetricField<Norm>& metric,
              const PropagationOptions& options)
      : domain_(domain),
        metric_(metric),
        options_(options),
        state_(makeLargeArray<VertexState>(domain.vertexCount(),
                                           {kUnreachable, kNoVertex, FrontQueue::kUnseen})),
        queue_(&state_.data()->queueSlot, kRecordWordsLog2) {}

  PropagationResult run(const std::vector<VertexId>& sources) {
    for (const VertexId s : sources) {
      state_[s].distance = 0.0;
      queue_.pushOrDecrease(s, 0.0);
    }
    std::vector<std::uint8_t> isTarget;
    std::size_t remainingTargets = 0;
    if (!options_.targets.empty()) {
      isTarget.assign(domain_.vertexCount(), 0);
      for (const VertexId t : options_.targets) {
        remainingTargets += isTarget[t] == 0 ? 1 : 0;
        isTarget[t] = 1;
      }
    }

    // STVD with k = 1 runs the vector code with an empty memory; that it
    // matches Dijkstra bit for bit is tested.
    const int k = options_.k;
    if (options_.method == Method::Dijkstra) {
      loop(isTarget, remainingTargets, [this](VertexId v) { relaxDijkstra(v); });
    } else if (options_.chainMeasure == ChainMeasure::ProjectionWeighted) {
      runVector<ChainMeasure::ProjectionWeighted>(k, isTarget, remainingTargets);
    } else {
      runVector<ChainMeasure::LargestEdgeNorm>(k, isTarget, remainingTargets);
    }

    PropagationResult result;
    // Only final vertices carry a distance; everything else is unreachable.
    // The result arrays are written once in order, so they gain nothing from
    // huge pages, and on a virtual machine fresh huge pages can cost several
    // times more to touch first than small ones (docs/performance.md).
    result.distance = std::vector<double>(domain_.vertexCount(), kUnreachable);
    result.predecessor = std::vector<VertexId>(domain_.vertexCount(), kNoVertex);
    for (VertexId v = 0; v < domain_.vertexCount(); ++v) {
      if (queue_.isFinal(v)) {
        result.distance[v] = state_[v].distance;
        result.predecessor[v] = state_[v].predecessor;
      }
    }
    result.termination = termination_;
    result.finalizedVertices = finalized_;
    result.relaxedEdges = relaxed_;
    // The records and the result arrays coexist while the latter are filled.
    peakBytes_ = std::max(peakBytes_, stateBytes() + result.distance.capacity() * sizeof(double) +
                                          result.predecessor.capacity() * sizeof(VertexId));
    result.peakStateBytes = peakBytes_ + isTarget.capacity();
    return result;
  }

 private:
  template <ChainMeasure Measure>
  void runVector(int k, const std::vector<std::uint8_t>& isTarget, std::size_t remainingTargets) {
    loop(isTarget, remainingTargets, [this, k](VertexId v) { relaxVector<Measure>(v, k); });
  }

  template <class Relax>
  void loop(const std::vector<std::uint8_t>& isTarget, std::size_t remainingTargets,
            Relax&& relax) {
    constexpr std::uint64_t kProgressInterval = 1u << 16;
    PropagationProgress progress;
    progress.domainVertices = domain_.domainVertexCount();
    while (!queue_.empty()) {
      if (queue_.minKey() > options_.maxDistance) {
        termination_ = Termination::MaxDistanceReached;
        break;
      }
      const VertexId v = queue_.popMin();
      ++finalized_;
      if (!queue_.empty()) prefetchNeighborhood(queue_.minVertex());
      if (!isTarget.empty() && isTarget[v] && --remainingTargets == 0) {
        termination_ = Termination::TargetsReached;
        break;
      }
      if (options_.progress && finalized_ % kProgressInterval == 0) {
        peakBytes_ = std::max(peakBytes_, stateBytes());
        progress.finalizedVertices = finalized_;
        progress.frontDistance = state_[v].distance;
        if (!options_.progress(progress)) {
          termination_ = Termination::Cancelled;
          break;
        }
      }
      relax(v);
      if (options_.method != Method::Dijkstra && !queue_.empty()) prefetchChain(queue_.minVertex());
    }
    peakBytes_ = std::max(peakBytes_, stateBytes());
  }

  // The vertex now at the top of the queue is nearly always the next one
  // popped. Asking for its neighbours' records and tensors (and what the
  // domain reads to form their edge vectors) while v is relaxed overlaps
  // the cache misses of the two pops.
  STVD_ALWAYS_INLINE void prefetchNeighborhood(VertexId u) {
    if constexpr (kPrefetches) {
      domain_.forEachNeighborRun(u, [&](VertexId first, VertexId last) {
        prefetchRange(&state_[first], &state_[last]);
        prefetchRange(&metric_[first], &metric_[last]);
      });
      domain_.prefetchNeighborGeometry(u);
    }
  }

  // STVD also reads the predecessor chain of the next vertex u: dependent
  // loads reaching k - 1 voxels behind the front, into voxels popped long
  // ago. Once u's neighbourhood has arrived (after v's relaxation), the
  // first two links are known; the rest of the chain is guessed to go on by
  // the second link's offset, as it does where the front is straight. Only
  // a grid's numbering makes that guess meaningful.
  STVD_ALWAYS_INLINE void prefetchChain(VertexId u) {
    if constexpr (std::is_same_v<Domain, VoxelGridDomain>) {
      const VertexId p1 = state_[u].predecessor;
      if (p1 == kNoVertex) return;
      const VertexId p2 = state_[p1].predecessor;
      if (p2 == kNoVertex) return;
      const std::int64_t step = static_cast<std::int64_t>(p2) - static_cast<std::int64_t>(p1);
      const std::int64_t count = static_cast<std::int64_t>(state_.size());
      std::int64_t guess = p2;
      for (int m = 2; m < options_.k && guess >= 0 && guess < count; ++m, guess += step) {
        detail::prefetch(&state_[static_cast<std::size_t>(guess)]);
        detail::prefetch(&metric_[static_cast<std::size_t>(guess)]);
      }
    }
  }

  std::uint64_t stateBytes() const {
    return state_.capacity() * sizeof(VertexState) + queue_.capacityBytes();
  }

  void update(VertexId w, VertexId v, double candidate) {
    VertexState& sw = state_[w];
    if (candidate < sw.distance) {
      sw.distance = candidate;
      sw.predecessor = v;
      queue_.pushOrDecrease(w, candidate);
    }
  }

  // Gathers the neighbours of v that are not final, with their edge vector
  // and edge norm, in batches; `flush` computes and applies the candidates
  // of a full batch (and of the last one).
  template <class Flush>
  STVD_ALWAYS_INLINE void forEachNeighborBatch(VertexId v, NeighborBatch<Norm>& batch,
                                               Flush&& flush) {
    const auto& pv = metric_[v];
    batch.size = 0;
    domain_.forEachNeighbor(v, [&](VertexId w, Vec3f e) STVD_ALWAYS_INLINE_LAMBDA {
      if (queue_.isFinal(w)) return;
      // Norm::edgeParams(pv, metric_[w]) for domains in R^3; a surface
      // carries the norm into v's tangent frame (chain_unfolding.hpp).
      batch.add(w, e, ChainUnfolding<Domain>::template edgeNorm<Norm>(domain_, pv, metric_[w], v, w, e));
      if (batch.size == NeighborBatch<Norm>::kCapacity) {
        batch.pad();
        flush(batch);
        batch.size = 0;
      }
    });
    if (batch.size > 0) {
      batch.pad();
      flush(batch);
    }
  }

  STVD_ALWAYS_INLINE void applyCandidates(VertexId v, const NeighborBatch<Norm>& batch) {
    relaxed_ += static_cast<std::uint64_t>(batch.size);
    for (int n = 0; n < batch.size; ++n) update(batch.vertex[n], v, batch.best[n]);
  }

  STVD_HOT_LOOP void relaxDijkstra(VertexId v) {
    const double dv = state_[v].distance;
    NeighborBatch<Norm> batch;
    forEachNeighborBatch(v, batch, [&](NeighborBatch<Norm>& b) STVD_ALWAYS_INLINE_LAMBDA {
      b.setDijkstraCandidates(dv);
      applyCandidates(v, b);
    });
  }

  // STVD update of every neighbour w of v (see ChainMemory).
  template <ChainMeasure Measure>
  STVD_HOT_LOOP void relaxVector(VertexId v, int k) {
    VertexId chain[kMaxMemoryDepth];
    int count = 1;
    chain[0] = v;
    while (count < k && state_[chain[count - 1]].predecessor != kNoVertex) {
      chain[count] = state_[chain[count - 1]].predecessor;
      ++count;
    }
    ChainMemory<Norm> memory;
    memory.edgeCount = count;
    Vec3f p[kMaxMemoryDepth];
    ChainUnfolding<Domain>::place(domain_, chain, count, p);
    for (int j = 2; j <= count; ++j) {
      memory.edge[j] = p[j - 2] - p[j - 1];
      // The norm in the unfolded frame (Norm::edgeParams of the end points
      // for domains in R^3; see chain_unfolding.hpp).
      memory.edgeNorm[j] = ChainUnfolding<Domain>::template edgeNorm<Norm>(
          domain_, metric_[chain[j - 1]], metric_[chain[j - 2]], chain[j - 1], chain[j - 2],
          memory.edge[j]);
    }
    for (int lane = 0; lane + 1 < count; ++lane) {
      memory.backX[lane] = p[lane + 1].x;
      memory.backY[lane] = p[lane + 1].y;
      memory.backZ[lane] = p[lane + 1].z;
      memory.baseDistance[lane] = state_[chain[lane + 1]].distance;
    }

    const double dv = state_[v].distance;
    NeighborBatch<Norm> batch;
    forEachNeighborBatch(v, batch, [&](NeighborBatch<Norm>& b) STVD_ALWAYS_INLINE_LAMBDA {
      // i = 1 is the Dijkstra term, measured exactly as Dijkstra measures it.
      b.setDijkstraCandidates(dv);
      lowerToChainCandidates<Measure>(memory, b);
      applyCandidates(v, b);
    });
  }

  const Domain& domain_;
  const MetricField<Norm>& metric_;
  const PropagationOptions& options_;
  // What the propagation knows of a vertex, in one 16-byte record: a
  // neighbour's distance and queue slot are read together, and with three
  // separate arrays each look at a neighbour cost up to three cache lines.
  struct VertexState {
    double distance;
    VertexId predecessor;
    std::uint32_t queueSlot;  // FrontQueue's slot
  };
  // FrontQueue finds the slot of vertex v at word v << kRecordWordsLog2
  // from the first record's slot.
  static constexpr unsigned kRecordWordsLog2 = 2;
  static_assert(sizeof(VertexState) == sizeof(std::uint32_t) << kRecordWordsLog2,
                "one record per 16 bytes");
  // Prefetching needs the domain's runs of neighbour numbers: rows of the
  // stencil's block on a grid, single vertices from the adjacency list of a
  // cell mesh. Surfaces are not prefetched (not tried): measuring their
  // edges also reads the end points' positions and normals.
  static constexpr bool kPrefetches =
      std::is_same_v<Domain, VoxelGridDomain> || std::is_same_v<Domain, CellMeshDomain>;
  std::vector<VertexState> state_;
  FrontQueue queue_;
  Termination termination_ = Termination::Completed;
  std::uint64_t finalized_ = 0;
  std::uint64_t relaxed_ = 0;
  std::uint64_t peakBytes_ = 0;
};

}  // namespace detail

template <class Domain, class Norm>
PropagationResult propagate(const Domain& domain, const MetricField<Norm>& metric,
                            const std::vector<VertexId>& sources,
                            const PropagationOptions& options) {
  if (metric.size() != domain.vertexCount())
    throw std::invalid_argument("metric has " + std::to_string(metric.size()) +
                                " vertices but the domain has " +
                                std::to_string(domain.vertexCount()));
  if (sources.empty()) throw std::invalid_argument("no source vertex given");
  for (const VertexId s : sources)
    if (!domain.contains(s))
      throw std::invalid_argument("source vertex " + std::to_string(s) +
                                  " lies outside the domain");
  for (const VertexId t : options.targets)
    if (!domain.contains(t))
      throw std::invalid_argument("target vertex " + std::to_string(t) +
                                  " lies outside the domain");
  if (options.method == Method::ShortTermVectorDijkstra &&
      (options.k < 1 || options.k > kMaxMemoryDepth))
    throw std::invalid_argument("STVD memory depth k = " + std::to_string(options.k) +
                                " is outside 1.." + std::to_string(kMaxMemoryDepth));
  if (std::isnan(options.maxDistance))
    throw std::invalid_argument("maximum distance is NaN");
  return detail::Propagation<Domain, Norm>(domain, metric, options).run(sources);
}

}  // namespace stvd
