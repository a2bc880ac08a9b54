// The path of an STVD candidate on a voxel grid: the straight segment
// between two voxel centres, used only inside the domain's region and
// measured with the metric interpolated along it.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <cstdint>
#include <cstring>
#include <type_traits>

#include "stvd/metric/norms.hpp"
#include "stvd/propagation/candidate_path.hpp"
#include "stvd/propagation/propagation.hpp"
#include "stvd/voxel_grid/voxel_grid_domain.hpp"

namespace stvd {

/// On a grid the candidate i of neighbour w is the segment from the centre
/// of c_{i-1} to the centre of w.
///
/// accepts(): VoxelGridDomain::segmentInDomain, so that no candidate cuts a
/// corner of the mask, jumps a wall or passes a gap the connectivity does
/// not join. A chain that stays farther from every excluded voxel than it
/// reaches is not checked at all.
///
/// length(): the midpoint rule with one sample per voxel step along the
/// segment (n = its length in index space under the maximum norm, which is
/// at most i for a chain of i edges of the 26-neighbourhood): the samples sit
/// at the midpoints of n equal sub-intervals, and at each the norm is the
/// trilinear interpolation of the voxels' parameters (for Riemannian norms,
/// of the tensors G; every norm's parameters here are plain structs of
/// floats, interpolated component by component, which keeps them valid: a
/// convex combination of positive-definite tensors, or of Randers
/// parameters, is one). The sample positions are rationals with denominator
/// 2n, computed exactly, so a sample on a cell face never gives weight to,
/// or reads, a voxel beyond it: all voxels read are those segmentInDomain
/// checked.
template <class Norm>
class VoxelGridCandidatePath {
 public:
  using Params = typename Norm::VertexParams;
  static_assert(std::is_trivially_copyable_v<Params> && sizeof(Params) % sizeof(float) == 0,
                "grid segments interpolate Norm::VertexParams as a plain struct of floats");

  VoxelGridCandidatePath(const VoxelGridDomain& domain, const MetricField<Norm>& metric)
      : domain_(domain), metric_(metric),
        longSteps_(domain.stencil().radius() > 1 && ExactInEveryDirection<Norm>::value),
        lookup_(EdgeRuleIsMean<Norm>::value ? metric.sharedLookup() : nullptr) {}

  /// Whether the stencil has steps that span more than one voxel step (the
  /// 98- and 290-neighbourhoods), which every method then measures along
  /// themselves (longStepLength), for norms that measure a straight segment
  /// exactly in every direction. With the edge rule of its two end points a
  /// step of three voxels ignored the two voxels between them, and could
  /// pass an expensive voxel for the price of the cheap ones at its ends:
  /// on the shipped brain Dijkstra on the 290-neighbourhood came out 3.8 %
  /// below Lanthier's converged distances in the median (p5 -7.6 %), and on
  /// the curved phantom (64^3) 2.7 % below exact, where the 26-neighbourhood
  /// stays within 0.33 % (docs/accuracy.md, "Long stencil steps"). A lattice
  /// table's norm (FOD) keeps the edge rule.
  bool measuresLongSteps() const { return longSteps_; }

  /// The length of the stencil step from v to its neighbour w measured
  /// along it (segmentLength: one sample per voxel step) when it spans more
  /// than one voxel step; -1 for a unit step, which keeps the edge rule of
  /// its end points, as on the 26-neighbourhood.
  STVD_ALWAYS_INLINE float longStepLength(VertexId v, VertexId w) const {
    return steps(v, w) > 1 ? segmentLength(v, w) : -1.f;
  }

  static constexpr bool measuresPaths() { return true; }
  /// A pending candidate is measured from its two end points alone
  /// (segmentLength), without its chain.
  static constexpr bool usesPlacedChain() { return false; }

  STVD_ALWAYS_INLINE void beginChain(const VertexId* chain, int count, const Vec3f* placed) {
    (void)placed;  // a segment's vector comes from its end points' indices
    chain_ = chain;
    // Every candidate's segment stays within the Chebyshev ball around v
    // that holds its ends: the farthest chain vertex, and w one stencil
    // radius away. With no excluded voxel that near, none can leave the
    // domain. (A chain with any-angle ancestors is not a chain of stencil
    // steps, so the reach is that of its vertices.)
    if (!domain_.hasMask() || count <= 1) {
      mayRefuse_ = false;
      return;
    }
    int reach = domain_.stencil().radius();
    for (int j = 1; j < count; ++j) reach = std::max(reach, steps(chain[0], chain[j]));
    mayRefuse_ = domain_.clearance()[chain[0]] <= reach;
  }

  /// What measuring the segment from a to b costs: its samples, the voxel
  /// steps between them (the Chebyshev distance of their indices).
  STVD_ALWAYS_INLINE int steps(VertexId a, VertexId b) const {
    return samplesAlong(domain_.indexOf(a), domain_.indexOf(b));
  }
  /// The default reach of an any-angle ancestor and of a source, in voxel
  /// steps (PropagationOptions::segmentReach, sourceReach): they grow with
  /// the resolution, the cube root of the voxels in the domain
  /// (anyAngleReach, candidate_path.hpp).
  int defaultReach() const { return anyAngleReach(domain_.domainVertexCount(), false); }
  int defaultSourceReach() const { return anyAngleReach(domain_.domainVertexCount(), true); }

  bool mayRefuse() const { return mayRefuse_; }

  STVD_ALWAYS_INLINE bool accepts(int i, VertexId w) const {
    return !mayRefuse_ || domain_.segmentInDomain(chain_[i - 1], w);
  }

  STVD_ALWAYS_INLINE float length(int i, VertexId w, Vec3f) {
    return accepts(i, w) ? segmentLength(chain_[i - 1], w) : kRefusedCandidate;
  }

  /// The length of the segment from the centre of `from` to the centre of
  /// w: length() without a chain, for a pending candidate, which accepts()
  /// let through when it became pending.
  STVD_ALWAYS_INLINE float segmentLength(VertexId from, VertexId w) const {
    const VoxelIndex a = domain_.indexOf(from), b = domain_.indexOf(w);
    const int i = samplesAlong(a, b);
    // The segment's vector in physical space, split into i equal pieces.
    const Vec3f piece = (1.f / static_cast<float>(i)) * domain_.indexOffsetVector(b.i - a.i, b.j - a.j, b.k - a.k);
    // Sample m lies at a + (2m + 1) d / (2i) in index space. Per axis it is
    // kept exactly as low + remainder / (2i), 0 <= remainder < 2i, and
    // stepped by 2d per sample.
    const int denominator = 2 * i;
    const float inverse = 1.f / static_cast<float>(denominator);
    const int d[3] = {b.i - a.i, b.j - a.j, b.k - a.k};
    int low[3] = {a.i, a.j, a.k}, remainder[3];
    for (int axis = 0; axis < 3; ++axis) {
      remainder[axis] = d[axis];  // the first sample: a + d / (2i)
      normalise(low[axis], remainder[axis], denominator);
    }
    const std::int64_t strideJ = static_cast<std::int64_t>(domain_.geometry().size[0]);
    const std::int64_t strideK = strideJ * static_cast<std::int64_t>(domain_.geometry().size[1]);
    // Where the norm's length reads a few of its parameters, chosen by the
    // vector (TableLookup), and the field holds the lookup's own parameters
    // alike in every voxel, the piece is looked up once and each sample
    // interpolates only those few: a lattice table's four entries of the
    // piece's square instead of the whole table. The same length as the
    // interpolated table's, which reads the same entries.
    [[maybe_unused]] typename LookupOf<Norm>::type look{};
    if constexpr (TableLookup<Norm>::value)
      if (lookup_) look = Norm::lookup(*lookup_, piece.x, piece.y, piece.z);
    float total = 0.f;
    for (int m = 0; m < i; ++m) {
      const float f[3] = {remainder[0] * inverse, remainder[1] * inverse, remainder[2] * inverse};
      // A corner beyond a face the sample lies on gets weight 0: its index
      // is that of the corner below, so no voxel outside the cell is read.
      const std::int64_t step[3] = {remainder[0] != 0 ? 1 : 0, remainder[1] != 0 ? strideJ : 0,
                                    remainder[2] != 0 ? strideK : 0};
      const std::int64_t origin = low[0] + strideJ * low[1] + strideK * low[2];
      // Trilinear weights, separable: x varies fastest over the 8 corners.
      const float wx[2] = {1.f - f[0], f[0]}, wy[2] = {1.f - f[1], f[1]}, wz[2] = {1.f - f[2], f[2]};
      float weight[8];
      const float* corner[8];
#pragma GCC unroll 8
      for (int n = 0; n < 8; ++n) {
        weight[n] = wx[n & 1] * wy[(n >> 1) & 1] * wz[n >> 2];
        const std::int64_t index =
            origin + ((n & 1) ? step[0] : 0) + ((n & 2) ? step[1] : 0) + ((n & 4) ? step[2] : 0);
        corner[n] = reinterpret_cast<const float*>(&metric_[static_cast<std::size_t>(index)]);
      }
      total += sampleLength(weight, corner, piece, look);
      for (int axis = 0; axis < 3; ++axis) {
        remainder[axis] += 2 * d[axis];
        normalise(low[axis], remainder[axis], denominator);
      }
    }
    return total;
  }

  /// Asks for nothing ahead of segmentLength(from, w). Asking for the voxel
  /// rows its samples read (four rows per sample, 256 requests for a
  /// segment from a source 64 steps away) filled the processor's few
  /// outstanding-miss slots while the previous vertex was relaxed, and
  /// stalled that relaxation instead: on the speed scene (128^3, k = 6)
  /// without it default STVD takes 3.0 to 3.3 times Dijkstra's time against
  /// 3.6 to 3.7 (one process each, alternating; results identical);
  /// prefetching the first sample's rows alone measured the same as none.
  STVD_ALWAYS_INLINE void prefetchSegment(VertexId, VertexId) const {}

 private:
  static constexpr int kFloats = static_cast<int>(sizeof(Params) / sizeof(float));

  template <class N, bool = TableLookup<N>::value>
  struct LookupOf {
    struct type {};
  };
  template <class N>
  struct LookupOf<N, true> {
    using type = typename N::Lookup;
  };

  // The norm at a sample (the trilinear weights of its 8 corners) along
  // the segment's piece: from the looked-up entries alone where the lookup
  // is shared, else from the interpolated parameters.
  STVD_ALWAYS_INLINE float sampleLength(const float (&weight)[8], const float* const (&corner)[8], Vec3f piece,
                                        const typename LookupOf<Norm>::type& look) const {
    if constexpr (TableLookup<Norm>::value) {
      if (lookup_) {
        float value[Norm::kLookupSlots];
#pragma GCC unroll 4
        for (int q = 0; q < Norm::kLookupSlots; ++q) {
          float sum = 0.f;
#pragma GCC unroll 8
          for (int n = 0; n < 8; ++n) sum += weight[n] * corner[n][look.slot[q]];
          value[q] = sum;
        }
        return Norm::lookupLength(look, value);
      }
    }
    (void)look;
    Params g;
    interpolate(weight, corner, g);
    // Where the edge rule is the mean of the end points', the norm of a
    // point is its own parameters: edgeParams(g, g) == g.
    if constexpr (EdgeRuleIsMean<Norm>::value)
      return Norm::length(g, piece.x, piece.y, piece.z);
    else
      return Norm::length(Norm::edgeParams(g, g), piece.x, piece.y, piece.z);
  }

  // g = sum_n weight[n] corner[n], component by component. (Loading each
  // corner into a vector register through memory was tried: 24 bytes
  // stored, 32 loaded, a store-forwarding stall per corner, a third slower.)
  STVD_ALWAYS_INLINE static void interpolate(const float (&weight)[8], const float* const (&corner)[8],
                                             Params& g) {
    float sum[kFloats];
#pragma GCC unroll 16
    for (int c = 0; c < kFloats; ++c) {
      float s = 0.f;
#pragma GCC unroll 8
      for (int n = 0; n < 8; ++n) s += weight[n] * corner[n][c];
      sum[c] = s;
    }
    std::memcpy(&g, sum, sizeof g);
  }

  // One sample per voxel step along the segment: its length in index space
  // under the maximum norm, the number of steps of a 26-connected line of
  // voxels from one end to the other. A chain of i edges of the 6-, 18- or
  // 26-neighbourhood spans at most i such steps; a longer stencil's edge
  // spans several.
  STVD_ALWAYS_INLINE static int samplesAlong(const VoxelIndex& a, const VoxelIndex& b) {
    return std::max({std::abs(b.i - a.i), std::abs(b.j - a.j), std::abs(b.k - a.k), 1});
  }

  // Brings remainder into [0, denominator), moving low by whole steps: a
  // sample moves by |d| / i <= the stencil radius per axis, so this loops
  // a few times at most.
  STVD_ALWAYS_INLINE static void normalise(int& low, int& remainder, int denominator) {
    while (remainder >= denominator) {
      remainder -= denominator;
      ++low;
    }
    while (remainder < 0) {
      remainder += denominator;
      --low;
    }
  }

  const VoxelGridDomain& domain_;
  const MetricField<Norm>& metric_;
  const VertexId* chain_ = nullptr;
  bool mayRefuse_ = false;
  const bool longSteps_;
  // metric.sharedLookup() where a point's norm is its own parameters (the
  // mean edge rule): one lookup per segment serves all its samples.
  const Params* const lookup_;
};

}  // namespace stvd
