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

#include "stvd/propagation/candidate_path.hpp"
#include "stvd/cell_mesh/cell_mesh_candidate_path.hpp"
#include "stvd/propagation/chain_unfolding.hpp"
#include "stvd/propagation/detail/front_queue.hpp"
#include "stvd/system/large_array.hpp"
#include "stvd/propagation/propagation.hpp"
#include "stvd/voxel_grid/voxel_grid_candidate_path.hpp"

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
  // Vertex norms for the chain-mean screen, as raw floats (no default
  // construction on every pop): v's, and per lane the sum of those of
  // c_0 .. c_{L+1}.
  static constexpr int kNormFloats = static_cast<int>(sizeof(typename Norm::VertexParams) / sizeof(float));
  float vertexNorm[kNormFloats];
  float chainNormSum[kMaxMemoryDepth][kNormFloats];
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
  int pendingLane[kCapacity];  // ChainMeasure::Segment: the lane of a pending candidate, or -1

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
  /// scale * (edge norm of neighbour n) + shift, component by component.
  STVD_ALWAYS_INLINE EdgeParams edgeNormAffine(int n, float scale, const float* shift) const {
    return gatherAffine(n, scale, shift, std::make_integer_sequence<int, kParamFloats>{});
  }
  template <int... C>
  STVD_ALWAYS_INLINE EdgeParams gatherAffine(int n, float scale, const float* shift,
                                             std::integer_sequence<int, C...>) const {
    return EdgeParams{(scale * param[C][n] + shift[C])...};
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

/// Per candidate lane L (candidate i = L + 2) and neighbour n, the length
/// l_g(E_i) that a chain rule gives the candidate (see ChainMemory): the
/// screen of ChainMeasure::Segment, or the value itself for the two chain
/// rules.
template <class Norm>
struct CandidateScreen {
  alignas(64) float length[kMaxMemoryDepth][NeighborBatch<Norm>::kCapacity];
};

/// Which chain rule a screen pass computes.
enum class ChainRule { ProjectionWeighted, LargestEdgeNorm, ChainMean };

/// Fills screen.length for every candidate i = 2..m+1 of every neighbour in
/// the batch, one candidate at a time and all neighbours at once.
///
/// ProjectionWeighted (section 6 of the paper):
///   l_g(E) = max(0, sum_j (e_j . Ebar) ||Ebar||_{g_j}),  Ebar = E / |E|:
/// E is split among its edges by their signed projections, and each portion
/// is measured with that edge's own norm.
/// LargestEdgeNorm:
///   l_g(E) = |E| max_j ||Ebar||_{g_j}:
/// the whole of E is measured with the most expensive of the chain's norms
/// in its direction.
/// ChainMean (a screen only):
///   l_g(E) = ||E|| under the mean of the norms at c_0 .. c_{i-1} and w;
/// w's norm is recovered from edge 1's, the mean of v's and w's (used only
/// where the norm's edge rule is that mean: EdgeRuleIsMean).
/// A constant norm gives exactly |E| ||Ebar|| = ||E|| with every rule.
template <ChainRule Rule, class Norm>
STVD_ALWAYS_INLINE void screenChainCandidates(const ChainMemory<Norm>& chain, const NeighborBatch<Norm>& batch,
                                              CandidateScreen<Norm>& screen) {
  constexpr int kCapacity = NeighborBatch<Norm>::kCapacity;
  const int size = batch.padded;
  alignas(64) float ux[kCapacity], uy[kCapacity], uz[kCapacity], acc[kCapacity], length[kCapacity];
  for (int lane = 0; lane + 2 <= chain.edgeCount; ++lane) {
    const int i = lane + 2;  // candidate i sums edges 1..i
    const float bx = chain.backX[lane], by = chain.backY[lane], bz = chain.backZ[lane];
    float* out = screen.length[lane];
    if constexpr (Rule == ChainRule::ChainMean) {
      // The mean of the tensors of c_0 .. c_{i-1} and w is
      // (S + 2 G_e - G_v) / (i + 1), S the sum of the first i, G_e edge 1's
      // norm (the mean of G_v and G_w): scale * G_e + shift.
      constexpr int kFloats = NeighborBatch<Norm>::kParamFloats;
      const float weight = 1.f / static_cast<float>(i + 1), scale = 2.f * weight;
      float shift[kFloats];
      for (int f = 0; f < kFloats; ++f) shift[f] = weight * (chain.chainNormSum[lane][f] - chain.vertexNorm[f]);
      STVD_SIMD_LOOP
      for (int n = 0; n < size; ++n) {
        const float ex = batch.ex[n] - bx, ey = batch.ey[n] - by, ez = batch.ez[n] - bz;
        out[n] = Norm::length(batch.edgeNormAffine(n, scale, shift), ex, ey, ez);
      }
      continue;
    }
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
      if constexpr (Rule == ChainRule::ProjectionWeighted)
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
        if constexpr (Rule == ChainRule::ProjectionWeighted)
          acc[n] += (ej.x * ux[n] + ej.y * uy[n] + ej.z * uz[n]) * normJ;
        else
          acc[n] = std::max(acc[n], normJ);
      }
    }
    STVD_SIMD_LOOP
    for (int n = 0; n < size; ++n)
      out[n] = Rule == ChainRule::ProjectionWeighted ? std::max(acc[n], 0.f) : length[n] * acc[n];
  }
}

/// The smallest base + screened length over the candidates of each
/// neighbour, and its lane (-1 where no candidate exists).
template <class Norm>
STVD_ALWAYS_INLINE void bestScreenedCandidates(const ChainMemory<Norm>& chain, const NeighborBatch<Norm>& batch,
                                               const CandidateScreen<Norm>& screen, double* value, int* lane) {
  const int size = batch.padded;
  // The lane is tracked as a double, beside the value, and every store is
  // unconditional. Written as `x = lower ? new : x`, GCC 12 made the updates
  // masked stores, which the next candidate's loads cannot forward from (a
  // stall per lane group and candidate: about 9 % of default STVD's time at
  // 128^3); with an int lane, or the candidates as the inner loop, it did
  // not vectorise at all.
  alignas(64) double laneValue[NeighborBatch<Norm>::kCapacity];
  STVD_SIMD_LOOP
  for (int n = 0; n < size; ++n) {
    value[n] = kUnreachable;
    laneValue[n] = -1.0;
  }
  for (int l = 0; l + 2 <= chain.edgeCount; ++l) {
    const double base = chain.baseDistance[l];
    const double thisLane = static_cast<double>(l);
    const float* length = screen.length[l];
    STVD_SIMD_LOOP
    for (int n = 0; n < size; ++n) {
      const double candidate = base + static_cast<double>(length[n]);
      const double old = value[n];
      const bool lower = candidate < old;
      laneValue[n] += (lower ? 1.0 : 0.0) * (thisLane - laneValue[n]);
      value[n] = lower ? candidate : old;
    }
  }
  STVD_SIMD_LOOP
  for (int n = 0; n < size; ++n) lane[n] = static_cast<int>(laneValue[n]);
}

/// Lowers best[n] of every neighbour to base + screened length of every
/// candidate: the two chain rules where no candidate can leave the domain.
template <class Norm>
STVD_ALWAYS_INLINE void lowerToScreenedCandidates(const ChainMemory<Norm>& chain, NeighborBatch<Norm>& batch,
                                                  const CandidateScreen<Norm>& screen) {
  const int size = batch.padded;
  for (int lane = 0; lane + 2 <= chain.edgeCount; ++lane) {
    const double base = chain.baseDistance[lane];
    const float* l = screen.length[lane];
    STVD_SIMD_LOOP
    for (int n = 0; n < size; ++n) batch.best[n] = std::min(batch.best[n], base + static_cast<double>(l[n]));
  }
}

/// What the propagation knows of a vertex, in one record: a neighbour's
/// distance and queue slot are read together, and with separate arrays each
/// look at a neighbour costs several cache lines.
template <bool Deferred>
struct VertexRecord;

/// Dijkstra and the chain rules: 16 bytes.
template <>
struct VertexRecord<false> {
  double distance;  // the key in the queue; the distance once final
  VertexId predecessor;
  std::uint32_t queueSlot;  // FrontQueue's slot

  static VertexRecord unseen() { return {kUnreachable, kNoVertex, FrontQueue::kUnseen}; }
  double key() const { return distance; }
  double finalDistance() const { return distance; }
};

/// ChainMeasure::Segment with deferred measurement (see
/// Propagation::settleMin): 32 bytes.
///
/// The key, the measured predecessor and the pending candidate matter only
/// until the vertex is final; from then on the same bytes hold its next
/// ancestors (pred(pred(v)) onwards). A relaxation then reads the whole
/// predecessor chain of k <= 2 + kStoredAncestors vertices from v's record
/// and its predecessor's, instead of walking it record by record: a walk of
/// dependent loads into voxels finalised long ago, each a likely cache miss
/// that the next could not overlap.
template <>
struct VertexRecord<true> {
  static constexpr int kStoredAncestors = 4;
  /// What a vertex not yet final carries.
  struct Open {
    double key;                    // the key in the queue: a pending candidate's screen, or `measured`
    VertexId measuredPredecessor;  // the vertex whose relaxation gave `measured`
    VertexId pendingBase;          // c_{i-1} of the pending candidate; kNoVertex for none
  };

  double measured;           // shortest measured distance: the distance once final
  std::uint32_t queueSlot;   // FrontQueue's slot
  VertexId predecessor;      // the vertex whose relaxation gave the key
  union {
    Open open;                                // until the vertex is final
    VertexId ancestors[kStoredAncestors];     // once it is relaxed: c_2, c_3, ... of its chain
  };

  static VertexRecord unseen() {
    VertexRecord r;
    r.measured = kUnreachable;
    r.queueSlot = FrontQueue::kUnseen;
    r.predecessor = kNoVertex;
    r.open = Open{kUnreachable, kNoVertex, kNoVertex};
    return r;
  }
  double finalDistance() const { return measured; }
};

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

/// A domain's CandidatePath, given the options where it takes them (a
/// surface checks the segment measure's lines only, and leaves the chain
/// rules as the paper defines them).
template <class Domain, class Norm>
CandidatePath<Domain, Norm> makeCandidatePath(const Domain& domain, const MetricField<Norm>& metric,
                                              const PropagationOptions& options) {
  if constexpr (std::is_constructible_v<CandidatePath<Domain, Norm>, const Domain&, const MetricField<Norm>&,
                                        const PropagationOptions&>)
    return CandidatePath<Domain, Norm>(domain, metric, options);
  else
    return CandidatePath<Domain, Norm>(domain, metric);
}

template <class Domain, class Norm, bool Deferred>
class Propagation {
  using VertexState = VertexRecord<Deferred>;

 public:
  Propagation(const Domain& domain, const MetricField<Norm>& metric,
              const PropagationOptions& options)
      : domain_(domain),
        metric_(metric),
        options_(options),
        state_(makeLargeArray<VertexState>(domain.vertexCount(), VertexState::unseen())),
        queue_(&state_.data()->queueSlot, kRecordWordsLog2),
        edgeMetric_(ChainUnfolding<Domain>::edgeMetric(domain, metric, options)),
        path_(makeCandidatePath(domain, metric, options)) {}

  PropagationResult run(const std::vector<VertexId>& sources) {
    for (const VertexId s : sources) {
      if constexpr (Deferred) {
        state_[s].measured = 0.0;
        state_[s].open.key = 0.0;
      } else {
        state_[s].distance = 0.0;
      }
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
    const int k = memoryDepth<Domain>(options_);
    if constexpr (Deferred) {
      if (options_.segmentScreen == SegmentScreen::ChainMean && ChainUnfolding<Domain>::kEdgeNormIsMean &&
          EdgeRuleIsMean<Norm>::value)
        runVector<ChainRule::ChainMean>(k, isTarget, remainingTargets);
      else
        runVector<ChainRule::ProjectionWeighted>(k, isTarget, remainingTargets);
    } else if (options_.method == Method::Dijkstra) {
      loop(isTarget, remainingTargets, [this](VertexId v) { relaxDijkstra(v); });
    } else if (options_.chainMeasure == ChainMeasure::ProjectionWeighted) {
      runVector<ChainRule::ProjectionWeighted>(k, isTarget, remainingTargets);
    } else {
      // LargestEdgeNorm, and the segment measure on a domain that cannot
      // measure along a path (CandidatePath), which falls back to the rule
      // that cannot go below the admissible bound.
      runVector<ChainRule::LargestEdgeNorm>(k, isTarget, remainingTargets);
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
        if (Deferred && state_[v].finalDistance() > options_.maxDistance) {
          --finalized_;  // settled a little beyond the limit: not reached
          continue;
        }
        result.distance[v] = state_[v].finalDistance();
        result.predecessor[v] = state_[v].predecessor;
      }
    }
    result.termination = termination_;
    result.finalizedVertices = finalized_;
    result.relaxedEdges = relaxed_;
    result.measuredCandidates = measured_;
    result.refusedCandidates = refused_;
    // The records and the result arrays coexist while the latter are filled.
    peakBytes_ = std::max(peakBytes_, stateBytes() + result.distance.capacity() * sizeof(double) +
                                          result.predecessor.capacity() * sizeof(VertexId));
    result.peakStateBytes = peakBytes_ + isTarget.capacity();
    return result;
  }

 private:
  template <ChainRule Rule>
  void runVector(int k, const std::vector<std::uint8_t>& isTarget, std::size_t remainingTargets) {
    loop(isTarget, remainingTargets, [this, k](VertexId v) { relaxVector<Rule>(v, k); });
  }

  template <class Relax>
  void loop(const std::vector<std::uint8_t>& isTarget, std::size_t remainingTargets,
            Relax&& relax) {
    constexpr std::uint64_t kProgressInterval = 1u << 16;
    PropagationProgress progress;
    progress.domainVertices = domain_.domainVertexCount();
    while (!queue_.empty()) {
      if (queue_.minKey() > options_.maxDistance) {
        // Deferred: a key may be a screened estimate, and a candidate
        // screened above the limit may measure below it; measure it before
        // stopping, so that a limit at a full run's largest distance
        // completes that run. (A vertex settled a little beyond the limit is
        // reported unreachable, run(), so that a run with a limit finalises
        // what a full run finalises first.)
        bool stop = true;
        if constexpr (Deferred) {
          if (state_[queue_.minVertex()].open.pendingBase != kNoVertex) {
            if (!settleMin()) continue;  // queued again with its measured distance
            stop = state_[queue_.minVertex()].finalDistance() > options_.maxDistance;
          }
        }
        if (stop) {
          termination_ = Termination::MaxDistanceReached;
          break;
        }
      } else if constexpr (Deferred) {
        if (!settleMin()) continue;
      }
      const VertexId v = queue_.popMin();
      ++finalized_;
      if (!queue_.empty()) {
        prefetchNeighborhood(queue_.minVertex());
        if constexpr (Deferred) prefetchPending(queue_.minVertex());
      }
      if (!isTarget.empty() && isTarget[v] && --remainingTargets == 0) {
        termination_ = Termination::TargetsReached;
        break;
      }
      if (options_.progress && finalized_ % kProgressInterval == 0) {
        peakBytes_ = std::max(peakBytes_, stateBytes());
        progress.finalizedVertices = finalized_;
        progress.frontDistance = state_[v].finalDistance();
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

  // The next vertex will most likely be settled next: when it has a pending
  // candidate, the data its measurement reads (long out of cache: the
  // candidate was found when the front was one edge behind) is asked for
  // while the current vertex is relaxed.
  STVD_ALWAYS_INLINE void prefetchPending(VertexId u) {
    if constexpr (!CandidatePath<Domain, Norm>::usesPlacedChain()) {
      const VertexId base = state_[u].open.pendingBase;
      if (base == kNoVertex) return;
      detail::prefetch(&state_[base]);
      path_.prefetchSegment(base, u);
    }
  }

  // STVD also reads the predecessor chain of the next vertex u: dependent
  // loads reaching k - 1 voxels behind the front, into voxels popped long
  // ago. With deferred measurement the chain is in two records (see
  // VertexRecord<true>). Otherwise, once u's neighbourhood has arrived
  // (after v's relaxation), the first two links are known; the rest of the
  // chain is guessed to go on by the second link's offset, as it does where
  // the front is straight. Only a grid's numbering makes that guess
  // meaningful.
  STVD_ALWAYS_INLINE void prefetchChain(VertexId u) {
    if constexpr (Deferred) {
      // Here the chain is known exactly: c_1's record (one of u's
      // neighbours, asked for with them) holds c_2 onwards.
      const VertexId p1 = state_[u].predecessor;
      if (p1 == kNoVertex) return;
      const VertexState& s1 = state_[p1];
      const int k = memoryDepth<Domain>(options_);
      for (int l = 2; l < k && l < 3 + VertexState::kStoredAncestors; ++l) {
        const VertexId c = l == 2 ? s1.predecessor : s1.ancestors[l - 3];
        if (c == kNoVertex) break;
        detail::prefetch(&state_[c]);
        detail::prefetch(&metric_[c]);
      }
    } else if constexpr (std::is_same_v<Domain, VoxelGridDomain>) {
      const VertexId p1 = state_[u].predecessor;
      if (p1 == kNoVertex) return;
      const VertexId p2 = state_[p1].predecessor;
      if (p2 == kNoVertex) return;
      const std::int64_t step = static_cast<std::int64_t>(p2) - static_cast<std::int64_t>(p1);
      const std::int64_t count = static_cast<std::int64_t>(state_.size());
      std::int64_t guess = p2;
      for (int m = 2; m < memoryDepth<Domain>(options_) && guess >= 0 && guess < count; ++m, guess += step) {
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
      batch.add(w, e, ChainUnfolding<Domain>::template edgeNorm<Norm>(domain_, edgeMetric_, pv, metric_[w], v, w, e));
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
    const double dv = state_[v].finalDistance();
    NeighborBatch<Norm> batch;
    forEachNeighborBatch(v, batch, [&](NeighborBatch<Norm>& b) STVD_ALWAYS_INLINE_LAMBDA {
      b.setDijkstraCandidates(dv);
      applyCandidates(v, b);
    });
  }

  // The predecessor chain c_0 = v, c_1 = pred(v), ... of the vertex v just
  // finalised, at most k vertices; returns their count. With deferred
  // measurement it first stores v's ancestors in its record (see
  // VertexRecord<true>), taken from its predecessor's, which was relaxed
  // before v could have it as predecessor.
  STVD_ALWAYS_INLINE int gatherChain(VertexId v, int k, VertexId* chain) {
    chain[0] = v;
    int count = 1;
    if constexpr (Deferred) {
      constexpr int kStored = VertexState::kStoredAncestors;
      VertexState& sv = state_[v];
      const VertexId p1 = sv.predecessor;
      VertexId stored[kStored];
      if (p1 == kNoVertex) {
        std::fill(stored, stored + kStored, kNoVertex);
      } else {
        const VertexState& s1 = state_[p1];
        stored[0] = s1.predecessor;
        for (int a = 1; a < kStored; ++a) stored[a] = s1.ancestors[a - 1];
        if (count < k) chain[count++] = p1;
        for (int a = 0; a < kStored && count < k && stored[a] != kNoVertex; ++a) chain[count++] = stored[a];
      }
      for (int a = 0; a < kStored; ++a) sv.ancestors[a] = stored[a];
    }
    while (count < k && state_[chain[count - 1]].predecessor != kNoVertex) {
      chain[count] = state_[chain[count - 1]].predecessor;
      ++count;
    }
    return count;
  }

  // STVD update of every neighbour w of v (see ChainMemory): the screen
  // ranks the candidates; with a chain rule (Measured false) the screened
  // value is the candidate's length, otherwise the best candidate that could
  // still win is measured along its path. Either way a candidate whose path
  // leaves the domain is refused and the next one tried.
  template <ChainRule Rule>
  STVD_HOT_LOOP void relaxVector(VertexId v, int k) {
    VertexId chain[kMaxMemoryDepth];
    const int count = gatherChain(v, k, chain);
    ChainMemory<Norm> memory;
    memory.edgeCount = count;
    Vec3f p[kMaxMemoryDepth];
    ChainUnfolding<Domain>::place(domain_, chain, count, p);
    // The chain's edges and their norms, which the two chain rules measure
    // with (the chain-mean screen needs only the vertices' norms).
    if constexpr (Rule != ChainRule::ChainMean) {
      for (int j = 2; j <= count; ++j) {
        memory.edge[j] = p[j - 2] - p[j - 1];
        // The norm in the unfolded frame (Norm::edgeParams of the end points
        // for domains in R^3; see chain_unfolding.hpp).
        memory.edgeNorm[j] = ChainUnfolding<Domain>::template edgeNorm<Norm>(
            domain_, edgeMetric_, metric_[chain[j - 1]], metric_[chain[j - 2]], chain[j - 1], chain[j - 2],
            memory.edge[j]);
      }
    }
    for (int lane = 0; lane + 1 < count; ++lane) {
      memory.backX[lane] = p[lane + 1].x;
      memory.backY[lane] = p[lane + 1].y;
      memory.backZ[lane] = p[lane + 1].z;
      memory.baseDistance[lane] = state_[chain[lane + 1]].finalDistance();
    }
    if constexpr (Rule == ChainRule::ChainMean) {
      std::memcpy(memory.vertexNorm, &metric_[v], sizeof memory.vertexNorm);
      constexpr int kFloats = ChainMemory<Norm>::kNormFloats;
      float sum[kFloats];
      std::memcpy(sum, &metric_[v], sizeof sum);
      for (int lane = 0; lane + 1 < count; ++lane) {
        float c[kFloats];
        std::memcpy(c, &metric_[chain[lane + 1]], sizeof c);
        for (int f = 0; f < kFloats; ++f) sum[f] += c[f];
        std::memcpy(memory.chainNormSum[lane], sum, sizeof sum);
      }
    }
    path_.beginChain(chain, count, p);
    const bool mayRefuse = path_.mayRefuse();

    const double dv = state_[v].finalDistance();
    NeighborBatch<Norm> batch;
    forEachNeighborBatch(v, batch, [&](NeighborBatch<Norm>& b) STVD_ALWAYS_INLINE_LAMBDA {
      // i = 1 is the Dijkstra term, measured exactly as Dijkstra measures it.
      b.setDijkstraCandidates(dv);
      if constexpr (Deferred) {
        if (count == 1) keepDijkstraTerms(v, b);
      }
      if (count > 1) {
        CandidateScreen<Norm> screen;
        screenChainCandidates<Rule>(memory, b, screen);
        if constexpr (Deferred)
          keepBestScreenedCandidates(v, memory, b, screen, mayRefuse);
        else if (mayRefuse)
          acceptBestCandidates(memory, b, screen);
        else
          lowerToScreenedCandidates(memory, b, screen);
      }
      if constexpr (Deferred)
        applyDeferred(v, b, chain);
      else
        applyCandidates(v, b);
    });
  }

  // The lane (candidate i = lane + 2) with the smallest screened value
  // among those not tried yet, or -1.
  STVD_ALWAYS_INLINE static int bestUntriedLane(const ChainMemory<Norm>& memory,
                                                const CandidateScreen<Norm>& screen, int n,
                                                unsigned tried, double& value) {
    int best = -1;
    value = kUnreachable;
    for (int lane = 0; lane + 2 <= memory.edgeCount; ++lane) {
      if ((tried >> lane) & 1u) continue;
      const double candidate = memory.baseDistance[lane] + static_cast<double>(screen.length[lane][n]);
      if (candidate < value) {
        value = candidate;
        best = lane;
      }
    }
    return best;
  }

  // Chain rules near the domain's boundary: the best screened candidate
  // whose path stays in the domain.
  STVD_ALWAYS_INLINE void acceptBestCandidates(const ChainMemory<Norm>& memory, NeighborBatch<Norm>& batch,
                            const CandidateScreen<Norm>& screen) {
    for (int n = 0; n < batch.size; ++n) {
      unsigned tried = 0;
      double value;
      for (int lane; (lane = bestUntriedLane(memory, screen, n, tried, value)) >= 0;) {
        if (!(value < batch.best[n])) break;
        tried |= 1u << lane;
        if (path_.accepts(lane + 2, batch.vertex[n])) {
          batch.best[n] = value;
          break;
        }
        ++refused_;
      }
    }
  }

  // ChainMeasure::Segment, deferred measurement (Deferred = true).
  // Measuring a candidate along its path costs several times its screen,
  // and a vertex is relaxed from a dozen neighbours whose best candidates
  // differ by fractions of a percent, so measuring at every relaxation would
  // measure nearly all of them (measured: 8 to 12 per vertex). Instead a
  // relaxation only screens: the Dijkstra term is exact and lowers the
  // vertex's measured distance (VertexRecord<true>::measured); the best
  // screened candidate, when its screened value is below everything the
  // vertex has, becomes its pending candidate, and that screened value its
  // key in the queue. When the vertex reaches the top of the queue, the
  // pending candidate is measured along its path (settleMin) and the vertex
  // is queued again with its measured distance; it is finalised only when
  // it reaches the top with nothing pending. So each vertex is measured
  // about once, and every distance it is finalised with is a measured one.

  // Records each neighbour's Dijkstra term as measured, and its best
  // screened candidate that stays in the domain as pending: best[n] becomes
  // the neighbour's new key, and pendingLane[n] says which candidate it is.
  STVD_ALWAYS_INLINE void keepBestScreenedCandidates(VertexId v, const ChainMemory<Norm>& memory,
                                                     NeighborBatch<Norm>& batch,
                                                     const CandidateScreen<Norm>& screen, bool mayRefuse) {
    alignas(64) double value[NeighborBatch<Norm>::kCapacity];
    alignas(64) int lane[NeighborBatch<Norm>::kCapacity];
    bestScreenedCandidates(memory, batch, screen, value, lane);
    for (int n = 0; n < batch.size; ++n) {
      const VertexId w = batch.vertex[n];
      keepMeasured(state_[w], batch.best[n], v);
      batch.pendingLane[n] = -1;
      // A candidate not below what w has (its Dijkstra term, or its key)
      // cannot become pending: no need to check its path.
      const double limit = std::min(batch.best[n], state_[w].open.key);
      if (!(value[n] < limit)) continue;
      if (measuresWhileChecking(path_)) {
        // Checking the paths measured them: every candidate is measured now,
        // and the shortest becomes a measured distance; nothing is pending.
        const Vec3f e{batch.ex[n], batch.ey[n], batch.ez[n]};
        double shortest = kUnreachable;
        for (int l = 0; l + 2 <= memory.edgeCount; ++l) {
          const float length = path_.length(l + 2, w, e);
          if (length == kRefusedCandidate) {
            ++refused_;
            continue;
          }
          ++measured_;
          shortest = std::min(shortest, memory.baseDistance[l] + static_cast<double>(length));
        }
        keepMeasured(state_[w], shortest, v);
        batch.best[n] = std::min(batch.best[n], shortest);
        continue;
      }
      if (!mayRefuse || path_.accepts(lane[n] + 2, w)) {
        batch.best[n] = value[n];
        batch.pendingLane[n] = lane[n];
        continue;
      }
      // Near the domain's boundary: the next best candidates in turn.
      ++refused_;
      unsigned tried = 1u << lane[n];
      double next;
      for (int l; (l = bestUntriedLane(memory, screen, n, tried, next)) >= 0;) {
        if (!(next < limit)) break;
        tried |= 1u << l;
        if (path_.accepts(l + 2, w)) {
          batch.best[n] = next;
          batch.pendingLane[n] = l;
          break;
        }
        ++refused_;
      }
    }
  }

  STVD_ALWAYS_INLINE static void keepMeasured(VertexState& s, double value, VertexId from) {
    if (value < s.measured) {
      s.measured = value;
      s.open.measuredPredecessor = from;
    }
  }

  // A chain of one vertex (a source) has no candidate beyond the Dijkstra term.
  STVD_ALWAYS_INLINE void keepDijkstraTerms(VertexId v, NeighborBatch<Norm>& batch) {
    for (int n = 0; n < batch.size; ++n) {
      keepMeasured(state_[batch.vertex[n]], batch.best[n], v);
      batch.pendingLane[n] = -1;
    }
  }

  STVD_ALWAYS_INLINE void applyDeferred(VertexId v, const NeighborBatch<Norm>& batch, const VertexId* chain) {
    relaxed_ += static_cast<std::uint64_t>(batch.size);
    for (int n = 0; n < batch.size; ++n) {
      const VertexId w = batch.vertex[n];
      VertexState& sw = state_[w];
      if (batch.best[n] < sw.open.key) {
        sw.open.key = batch.best[n];
        sw.predecessor = v;
        const int lane = batch.pendingLane[n];
        sw.open.pendingBase = lane < 0 ? kNoVertex : chain[lane + 1];
        queue_.pushOrDecrease(w, batch.best[n]);
      }
    }
  }

  // Measures the pending candidate of w (from its predecessor v) along its
  // path and keeps it when it is shorter than what w has measured.
  STVD_HOT_LOOP void measurePending(VertexId w, VertexState& sw) {
    const VertexId v = sw.predecessor, base = sw.open.pendingBase;
    sw.open.pendingBase = kNoVertex;
    float l;
    if constexpr (CandidatePath<Domain, Norm>::usesPlacedChain()) {
      // The path depends on the chain between c_{i-1} and v (a surface's
      // unfolding): rebuild it.
      VertexId chain[kMaxMemoryDepth];
      int i = 1;
      chain[0] = v;
      while (chain[i - 1] != base) {
        chain[i] = state_[chain[i - 1]].predecessor;
        ++i;
      }
      Vec3f p[kMaxMemoryDepth];
      ChainUnfolding<Domain>::place(domain_, chain, i, p);
      path_.beginChain(chain, i, p);
      l = path_.length(i, w, ChainUnfolding<Domain>::neighborEdge(domain_, v, w));
    } else {
      l = path_.segmentLength(base, w);
    }
    if (l == kRefusedCandidate) {
      ++refused_;
      return;
    }
    ++measured_;
    keepMeasured(sw, state_[base].measured + static_cast<double>(l), v);
  }

  // How far above its screened key a measured distance may lie for the
  // vertex to be finalised without going back into the queue.
  static constexpr double kSettleSlack = 0.01;

  // Makes the vertex at the top of the queue ready to be finalised: true
  // when its key is a measured distance. Otherwise its pending candidate is
  // measured along its path, the vertex is queued again with the shortest
  // measured distance it has, and false is returned (the top has changed).
  bool settleMin() {
    const VertexId w = queue_.minVertex();
    VertexState& sw = state_[w];
    if (sw.open.pendingBase != kNoVertex) {
      measurePending(w, sw);
      // A screen that was only a little too low (or too high: the measured
      // distance is then the vertex's smallest) leaves the vertex where it
      // is: it is finalised at once with its measured distance. Requeueing
      // it would move it down the heap and bring it up again later, cold:
      // measured on the curved scene at 128^3, that cost k = 8 a third of
      // its time and gained no accuracy (1.13 % against 1.09 % mean error).
      // STVD's front is not in exact order of distance anyway
      // (docs/architecture.md).
      if (sw.measured <= queue_.minKey() * (1.0 + kSettleSlack)) {
        sw.open.key = sw.measured;
        sw.predecessor = sw.open.measuredPredecessor;
        return true;
      }
    } else if (!(queue_.minKey() < sw.open.key)) {
      return true;  // measured, and queued with that distance
    }
    // The vertex's key was a screened estimate well below its measured
    // distance (or an entry left from an earlier key): queue it with its
    // measured distance.
    sw.open.key = sw.measured;
    sw.predecessor = sw.open.measuredPredecessor;
    queue_.requeueMin(sw.measured);
    return false;
  }

  const Domain& domain_;
  const MetricField<Norm>& metric_;
  const PropagationOptions& options_;
  // FrontQueue finds the slot of vertex v at word v << kRecordWordsLog2
  // from the first record's slot.
  static constexpr unsigned kRecordWordsLog2 = Deferred ? 3 : 2;
  static_assert(sizeof(VertexState) == sizeof(std::uint32_t) << kRecordWordsLog2,
                "one record per 16 or 32 bytes");
  // Prefetching needs the domain's runs of neighbour numbers: rows of the
  // stencil's block on a grid, single vertices from the adjacency list of a
  // cell mesh. Surfaces are not prefetched (not tried): measuring their
  // edges also reads the end points' positions and normals.
  static constexpr bool kPrefetches =
      std::is_same_v<Domain, VoxelGridDomain> || std::is_same_v<Domain, CellMeshDomain>;
  std::vector<VertexState> state_;
  FrontQueue queue_;
  const typename ChainUnfolding<Domain>::EdgeMetric edgeMetric_;
  CandidatePath<Domain, Norm> path_;
  Termination termination_ = Termination::Completed;
  std::uint64_t finalized_ = 0;
  std::uint64_t relaxed_ = 0;
  std::uint64_t measured_ = 0;
  std::uint64_t refused_ = 0;
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
  const int k = memoryDepth<Domain>(options);
  if (options.method == Method::ShortTermVectorDijkstra && (k < 1 || k > kMaxMemoryDepth))
    throw std::invalid_argument("STVD memory depth k = " + std::to_string(k) + " is outside 1.." +
                                std::to_string(kMaxMemoryDepth));
  if (std::isnan(options.maxDistance))
    throw std::invalid_argument("maximum distance is NaN");
  // ChainMeasure::Segment on a domain that measures along paths defers its
  // measurements, with a record of its own per vertex.
  if (options.method == Method::ShortTermVectorDijkstra && options.chainMeasure == ChainMeasure::Segment &&
      k > 1 && measuresPathsOn<Domain, Norm>(domain))
    return detail::Propagation<Domain, Norm, true>(domain, metric, options).run(sources);
  return detail::Propagation<Domain, Norm, false>(domain, metric, options).run(sources);
}

}  // namespace stvd
