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

#include "stvd/candidate_path.hpp"
#include "stvd/cell_mesh_candidate_path.hpp"
#include "stvd/chain_unfolding.hpp"
#include "stvd/detail/front_queue.hpp"
#include "stvd/large_array.hpp"
#include "stvd/propagation.hpp"
#include "stvd/voxel_grid_candidate_path.hpp"

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
/// w's norm is recovered from edge 1's, the mean of v's and w's (both
/// built-in norms' edge rule is that mean).
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
  STVD_SIMD_LOOP
  for (int n = 0; n < size; ++n) {
    value[n] = kUnreachable;
    lane[n] = -1;
  }
  for (int l = 0; l + 2 <= chain.edgeCount; ++l) {
    const double base = chain.baseDistance[l];
    const float* length = screen.length[l];
    STVD_SIMD_LOOP
    for (int n = 0; n < size; ++n) {
      const double candidate = base + static_cast<double>(length[n]);
      const bool lower = candidate < value[n];
      value[n] = lower ? candidate : value[n];
      lane[n] = lower ? l : lane[n];
    }
  }
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
        queue_(&state_.data()->queueSlot, kRecordWordsLog2),
        path_(domain, metric) {}

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
    constexpr bool kMeasures = CandidatePath<Domain, Norm>::measuresPaths();
    if (options_.method == Method::Dijkstra) {
      loop(isTarget, remainingTargets, [this](VertexId v) { relaxDijkstra(v); });
    } else if (options_.chainMeasure == ChainMeasure::ProjectionWeighted) {
      runVector<ChainRule::ProjectionWeighted, false>(k, isTarget, remainingTargets);
    } else if (options_.chainMeasure == ChainMeasure::LargestEdgeNorm || !kMeasures ||
               !measuresOnThisDomain(path_)) {
      // A domain that cannot measure along a path (CandidatePath) falls back
      // from the segment measure to the rule that cannot go below the
      // admissible bound.
      runVector<ChainRule::LargestEdgeNorm, false>(k, isTarget, remainingTargets);
    } else if (options_.segmentScreen == SegmentScreen::ChainMean && ChainUnfolding<Domain>::kEdgeNormIsMean) {
      runVector<ChainRule::ChainMean, kMeasures>(k, isTarget, remainingTargets);
    } else {
      runVector<ChainRule::ProjectionWeighted, kMeasures>(k, isTarget, remainingTargets);
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
    result.measuredCandidates = measured_;
    result.refusedCandidates = refused_;
    // The records and the result arrays coexist while the latter are filled.
    peakBytes_ = std::max(peakBytes_, stateBytes() + result.distance.capacity() * sizeof(double) +
                                          result.predecessor.capacity() * sizeof(VertexId));
    result.peakStateBytes = peakBytes_ + isTarget.capacity();
    return result;
  }

 private:
  template <ChainRule Rule, bool Measured>
  void runVector(int k, const std::vector<std::uint8_t>& isTarget, std::size_t remainingTargets) {
    if constexpr (Measured) {
      candidate_ = makeLargeArray<CandidateState>(domain_.vertexCount(), {kUnreachable, kNoVertex, 0});
      loop<true>(isTarget, remainingTargets, [this, k](VertexId v) { relaxVector<Rule, true>(v, k); });
    } else {
      loop(isTarget, remainingTargets, [this, k](VertexId v) { relaxVector<Rule, false>(v, k); });
    }
  }

  template <bool Deferred = false, class Relax>
  void loop(const std::vector<std::uint8_t>& isTarget, std::size_t remainingTargets,
            Relax&& relax) {
    constexpr std::uint64_t kProgressInterval = 1u << 16;
    PropagationProgress progress;
    progress.domainVertices = domain_.domainVertexCount();
    while (!queue_.empty()) {
      // A pending candidate's screened key may lie on either side of its
      // measured length, so only measured keys are held against the limit.
      if constexpr (Deferred) {
        if (!settleMin()) continue;
      }
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
        if (!candidate_.empty()) prefetchRange(&candidate_[first], &candidate_[last]);
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
    return state_.capacity() * sizeof(VertexState) + candidate_.capacity() * sizeof(CandidateState) +
           queue_.capacityBytes();
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

  // STVD update of every neighbour w of v (see ChainMemory): the screen
  // ranks the candidates; with a chain rule (Measured false) the screened
  // value is the candidate's length, otherwise the best candidate that could
  // still win is measured along its path. Either way a candidate whose path
  // leaves the domain is refused and the next one tried.
  template <ChainRule Rule, bool Measured>
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

    const double dv = state_[v].distance;
    NeighborBatch<Norm> batch;
    forEachNeighborBatch(v, batch, [&](NeighborBatch<Norm>& b) STVD_ALWAYS_INLINE_LAMBDA {
      // i = 1 is the Dijkstra term, measured exactly as Dijkstra measures it.
      b.setDijkstraCandidates(dv);
      if constexpr (Measured) {
        if (count == 1) keepDijkstraTerms(v, b);
      }
      if (count > 1) {
        CandidateScreen<Norm> screen;
        screenChainCandidates<Rule>(memory, b, screen);
        if constexpr (Measured)
          keepBestScreenedCandidates(v, memory, b, screen, mayRefuse);
        else if (mayRefuse)
          acceptBestCandidates(memory, b, screen);
        else
          lowerToScreenedCandidates(memory, b, screen);
      }
      if constexpr (Measured)
        applyDeferred(v, b);
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

  // ChainMeasure::Segment, deferred measurement. Measuring a candidate
  // along its path costs several times its screen, and a vertex is relaxed
  // from a dozen neighbours whose best candidates differ by fractions of a
  // percent, so measuring at every relaxation would measure nearly all of
  // them (measured: 8 to 12 per vertex). Instead a relaxation only screens:
  // the Dijkstra term is exact and lowers the vertex's measured distance
  // (CandidateState::measured); the best screened candidate, when its
  // screened value is below everything the vertex has, becomes its pending
  // candidate, and that screened value its key in the queue. When the
  // vertex reaches the top of the queue, the pending candidate is measured
  // along its path (settleMin) and the vertex is queued again with its
  // measured distance; it is finalised only when it reaches the top with
  // nothing pending. So each vertex is measured about once, and every
  // distance it is finalised with is a measured one.
  struct CandidateState {
    double measured;               // shortest measured distance so far
    VertexId measuredPredecessor;  // the vertex whose relaxation gave it
    std::uint32_t pendingSpan;     // i of the pending candidate, 0 for none
  };

  // Records each neighbour's Dijkstra term as measured, and its best
  // screened candidate that stays in the domain as pending: best[n] becomes
  // the neighbour's new key, and pendingLane[n] says which candidate it is.
  STVD_ALWAYS_INLINE void keepBestScreenedCandidates(VertexId v, const ChainMemory<Norm>& memory, NeighborBatch<Norm>& batch,
                                  const CandidateScreen<Norm>& screen, bool mayRefuse) {
    alignas(64) double value[NeighborBatch<Norm>::kCapacity];
    alignas(64) int lane[NeighborBatch<Norm>::kCapacity];
    bestScreenedCandidates(memory, batch, screen, value, lane);
    for (int n = 0; n < batch.size; ++n) {
      const VertexId w = batch.vertex[n];
      CandidateState& c = candidate_[w];
      if (batch.best[n] < c.measured) {
        c.measured = batch.best[n];
        c.measuredPredecessor = v;
      }
      batch.pendingLane[n] = -1;
      if (!(value[n] < batch.best[n])) continue;
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
        if (!(next < batch.best[n])) break;
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

  // A chain of one vertex (a source) has no candidate beyond the Dijkstra term.
  STVD_ALWAYS_INLINE void keepDijkstraTerms(VertexId v, NeighborBatch<Norm>& batch) {
    for (int n = 0; n < batch.size; ++n) {
      CandidateState& c = candidate_[batch.vertex[n]];
      if (batch.best[n] < c.measured) {
        c.measured = batch.best[n];
        c.measuredPredecessor = v;
      }
      batch.pendingLane[n] = -1;
    }
  }

  STVD_ALWAYS_INLINE void applyDeferred(VertexId v, const NeighborBatch<Norm>& batch) {
    relaxed_ += static_cast<std::uint64_t>(batch.size);
    for (int n = 0; n < batch.size; ++n) {
      const VertexId w = batch.vertex[n];
      VertexState& sw = state_[w];
      if (batch.best[n] < sw.distance) {
        sw.distance = batch.best[n];
        sw.predecessor = v;
        const int lane = batch.pendingLane[n];
        candidate_[w].pendingSpan = lane < 0 ? 0u : static_cast<std::uint32_t>(lane + 2);
        queue_.pushOrDecrease(w, batch.best[n]);
      }
    }
  }

  // Measures the pending candidate of w (from v) along its path and keeps
  // it when it is shorter than what w has measured.
  STVD_HOT_LOOP void measurePending(VertexId w, VertexId v, CandidateState& c) {
    const int i = static_cast<int>(c.pendingSpan);
    c.pendingSpan = 0;
    VertexId chain[kMaxMemoryDepth];
    chain[0] = v;
    for (int j = 1; j < i; ++j) chain[j] = state_[chain[j - 1]].predecessor;
    Vec3f p[kMaxMemoryDepth];
    ChainUnfolding<Domain>::place(domain_, chain, i, p);
    path_.beginChain(chain, i, p);
    const float l = path_.length(i, w, ChainUnfolding<Domain>::neighborEdge(domain_, v, w));
    if (l == kRefusedCandidate) {
      ++refused_;
      return;
    }
    ++measured_;
    const double value = state_[chain[i - 1]].distance + static_cast<double>(l);
    if (value < c.measured) {
      c.measured = value;
      c.measuredPredecessor = v;
    }
  }

  // Makes the vertex at the top of the queue ready to be finalised: true
  // when its key is a measured distance. Otherwise its pending candidate is
  // measured along its path, the vertex is queued again with the shortest
  // measured distance it has, and false is returned (the top has changed).
  bool settleMin() {
    const VertexId w = queue_.minVertex();
    VertexState& sw = state_[w];
    CandidateState& c = candidate_[w];
    if (c.pendingSpan >= 2) {
      measurePending(w, sw.predecessor, c);
    } else if (!(queue_.minKey() < sw.distance)) {
      return true;  // measured, and queued with that distance
    }
    // The vertex's key was a screened estimate (or an entry left from an
    // earlier key): queue it with its measured distance.
    sw.distance = c.measured;
    sw.predecessor = c.measuredPredecessor;
    queue_.requeueMin(c.measured);
    return false;
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
  CandidatePath<Domain, Norm> path_;
  std::vector<CandidateState> candidate_;  // ChainMeasure::Segment only
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
  if (options.method == Method::ShortTermVectorDijkstra &&
      (options.k < 1 || options.k > kMaxMemoryDepth))
    throw std::invalid_argument("STVD memory depth k = " + std::to_string(options.k) +
                                " is outside 1.." + std::to_string(kMaxMemoryDepth));
  if (std::isnan(options.maxDistance))
    throw std::invalid_argument("maximum distance is NaN");
  return detail::Propagation<Domain, Norm>(domain, metric, options).run(sources);
}

}  // namespace stvd
