// The chain screen of Short-Term Vector Dijkstra: when a vertex v is
// finalised, every candidate of every neighbour w (the path from chain
// vertex c_{i-1} to w that replaces i chain edges) is given a length by a
// chain rule, in loops vectorised across the neighbours. For the chain
// measures ProjectionWeighted and LargestEdgeNorm that length is the
// candidate's; for the segment measure it only ranks the candidates before
// the best one is measured along its path (relaxation.hpp). Internal to the
// propagation (docs/architecture.md, "Propagation").
#pragma once

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <limits>
#include <type_traits>
#include <utility>

#include "stvd/detail/compiler.hpp"
#include "stvd/propagation/propagation.hpp"
#include "stvd/types.hpp"

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
  float backX[kMaxChainLength], backY[kMaxChainLength], backZ[kMaxChainLength];  // x(c_{L+1}) - x(v)
  double baseDistance[kMaxChainLength];  // dist(c_{L+1})
  Vec3f edge[kMaxMemoryDepth + 1];             // e_j, j = 2..m+1
  EdgeParams edgeNorm[kMaxMemoryDepth + 1];
  // Vertex norms for the chain-mean screen, as raw floats (no default
  // construction on every pop): v's, and per lane the sum of those of
  // c_0 .. c_{L+1}.
  static constexpr int kNormFloats = static_cast<int>(sizeof(typename Norm::VertexParams) / sizeof(float));
  float vertexNorm[kNormFloats];
  float chainNormSum[kMaxMemoryDepth][kNormFloats];
  // Any-angle ancestors (Propagation::appendAnyAngleAncestors): lanes
  // latticeLanes.. are screened as the segment from the ancestor b measured
  // with the edge rule of v's and b's norms, scaled by the ratio of what
  // v's own path from b measured to what that norm gives it.
  int latticeLanes;
  EdgeParams ancestorNorm[kMaxAnyAngleAncestors];
  float ancestorRatio[kMaxAnyAngleAncestors];
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

  // By lookup (TableLookup, norms.hpp; set by beginByLookup, for norms
  // whose edge rule is the mean): the batch keeps no copy of the edge
  // norms, only where the relaxed vertex's and each neighbour's parameters
  // lie, and a vector is measured from the few of them its length reads,
  // chosen by `lookup` (the metric's sharedLookup, metric_field.hpp): a
  // lattice table's four entries of its 49. Only Dijkstra's candidates and
  // the chain-mean screen are computed so (the two chain rules read every
  // parameter of every edge).
  const typename Norm::VertexParams* lookup = nullptr;
  const float* base = nullptr;     // the metric's parameters as floats
  const float* near = nullptr;     // the relaxed vertex v's
  alignas(64) std::int64_t far[kCapacity];  // neighbour n's: base + far[n]
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
      // By lookup the padding is not measured (the loops of lookups are
      // not vector loops) and holds no parameters.
      if (!(TableLookup<Norm>::value && lookup))
        for (int c = 0; c < kParamFloats; ++c) param[c][n] = 0.f;
    }
  }
  /// Measures by lookup from here on: `metric` the field's parameters,
  /// v the relaxed vertex.
  STVD_ALWAYS_INLINE void beginByLookup(const typename Norm::VertexParams* shared,
                                        const typename Norm::VertexParams* metric, VertexId v) {
    lookup = shared;
    base = reinterpret_cast<const float*>(metric);
    near = base + static_cast<std::int64_t>(v) * kParamFloats;
  }
  STVD_ALWAYS_INLINE void addByLookup(VertexId w, Vec3f e) {
    vertex[size] = w;
    ex[size] = e.x;
    ey[size] = e.y;
    ez[size] = e.z;
    far[size] = static_cast<std::int64_t>(w) * kParamFloats;
    ++size;
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
    if constexpr (TableLookup<Norm>::value) {
      if (lookup) {
        // The edge rule is the mean (a lattice table's), as edgeParams
        // writes it, 0.5 (a + b), for the same bits.
        // The lanes past size are padding for vector loops, which this loop
        // is not: left out.
        alignas(64) float length[kCapacity];
        Norm::lookupLengths(*lookup, size, ex, ey, ez, 0.5f, near, base, far, length);
        for (int n = 0; n < size; ++n) best[n] = dv + static_cast<double>(length[n]);
        for (int n = size; n < padded; ++n) best[n] = kUnreachable;
        return;
      }
    }
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
  alignas(64) float length[kMaxChainLength][NeighborBatch<Norm>::kCapacity];
};

/// What a screen pass computes: the chain measure ProjectionWeighted or
/// LargestEdgeNorm (the candidates' lengths), or for ChainMeasure::Segment
/// its screen (SegmentScreen::ChainMean here; SegmentScreen::
/// ProjectionWeighted runs the ProjectionWeighted pass).
enum class ChainScreen { ProjectionWeighted, LargestEdgeNorm, ChainMean };

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
template <ChainScreen Screen, class Norm>
STVD_ALWAYS_INLINE void screenChainCandidates(const ChainMemory<Norm>& chain, const NeighborBatch<Norm>& batch,
                                              CandidateScreen<Norm>& screen) {
  constexpr int kCapacity = NeighborBatch<Norm>::kCapacity;
  const int size = batch.padded;
  alignas(64) float ux[kCapacity], uy[kCapacity], uz[kCapacity], acc[kCapacity], length[kCapacity];
  for (int lane = 0; lane + 2 <= chain.latticeLanes + 1; ++lane) {
    const int i = lane + 2;  // candidate i sums edges 1..i
    const float bx = chain.backX[lane], by = chain.backY[lane], bz = chain.backZ[lane];
    float* out = screen.length[lane];
    if constexpr (Screen == ChainScreen::ChainMean) {
      // The mean of the tensors of c_0 .. c_{i-1} and w is
      // (S + 2 G_e - G_v) / (i + 1), S the sum of the first i, G_e edge 1's
      // norm (the mean of G_v and G_w): scale * G_e + shift.
      constexpr int kFloats = NeighborBatch<Norm>::kParamFloats;
      const float weight = 1.f / static_cast<float>(i + 1), scale = 2.f * weight;
      if constexpr (TableLookup<Norm>::value) {
        if (batch.lookup) {
          // The same mean from G_w itself: (S + G_w) / (i + 1).
          // Only the batch's neighbours: the padding is for vector loops.
          for (int n = 0; n < batch.size; ++n) {
            ux[n] = batch.ex[n] - bx;
            uy[n] = batch.ey[n] - by;
            uz[n] = batch.ez[n] - bz;
          }
          Norm::lookupLengths(*batch.lookup, batch.size, ux, uy, uz, weight, chain.chainNormSum[lane], batch.base,
                              batch.far, out);
          for (int n = batch.size; n < size; ++n) out[n] = std::numeric_limits<float>::infinity();
          continue;
        }
      }
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
      if constexpr (Screen == ChainScreen::ProjectionWeighted)
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
        if constexpr (Screen == ChainScreen::ProjectionWeighted)
          acc[n] += (ej.x * ux[n] + ej.y * uy[n] + ej.z * uz[n]) * normJ;
        else
          acc[n] = std::max(acc[n], normJ);
      }
    }
    STVD_SIMD_LOOP
    for (int n = 0; n < size; ++n)
      out[n] = Screen == ChainScreen::ProjectionWeighted ? std::max(acc[n], 0.f) : length[n] * acc[n];
  }
}

/// Fills screen.length for the lanes of the chain's any-angle ancestors
/// (ChainMemory::ancestorNorm): the segment from the ancestor measured with
/// the edge rule of v's and its norms, times its ratio.
template <class Norm>
STVD_ALWAYS_INLINE void screenAnyAngleAncestors(const ChainMemory<Norm>& chain, const NeighborBatch<Norm>& batch,
                                                CandidateScreen<Norm>& screen) {
  const int size = batch.padded;
  for (int lane = chain.latticeLanes; lane + 2 <= chain.edgeCount; ++lane) {
    const float bx = chain.backX[lane], by = chain.backY[lane], bz = chain.backZ[lane];
    const typename Norm::EdgeParams g = chain.ancestorNorm[lane - chain.latticeLanes];
    const float ratio = chain.ancestorRatio[lane - chain.latticeLanes];
    float* out = screen.length[lane];
    STVD_SIMD_LOOP
    for (int n = 0; n < size; ++n) {
      const float ex = batch.ex[n] - bx, ey = batch.ey[n] - by, ez = batch.ez[n] - bz;
      out[n] = ratio * Norm::length(g, ex, ey, ez);
    }
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

}  // namespace detail
}  // namespace stvd
