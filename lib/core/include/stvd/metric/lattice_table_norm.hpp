// A symmetric norm given by a table of its values along the lattice
// directions of a voxel grid, interpolated linearly over the faces of the
// cube: the norm of a general (Finsler) metric that has no closed form,
// such as the convexified FOD norm (docs/fod.md, "STVD and Lanthier"), in a
// form that STVD's segment measure and Lanthier's cells evaluate in a few
// dozen flops, with no allocation, branch table or call per edge.
#pragma once

#include <algorithm>
#include <array>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <string>

#include "stvd/types.hpp"

namespace stvd {

/// The table: the lengths C_d = F(A d) of the physical vectors A d of the
/// index offsets d in {-n, ..., n}^3 whose largest component is n = Order
/// in absolute value (the lattice points on the surface of the cube of
/// radius n; 26 for n = 1, 98 for n = 2, 218 for n = 3), one of each pair
/// +-d (F symmetric): kCount = 13, 49, 109 values.
///
/// A vector v is measured in index space, f = A^-1 v: with m = |f|_inf along
/// axis a, the point p = (n / m) f lies on the cube's face p_a = +-n, in a
/// unit square of its lattice, and F(v) = (m / n) L(p), where L is the
/// linear interpolation of the table over the triangle of that square that
/// holds p; of the square's two diagonals, the one whose end values sum
/// less (the lower convex hull of the square's four values).
///
/// * Along a lattice direction (every neighbour step, for any n) the length
///   is the table's value: exact.
/// * Never below the norm tabulated: along a face (an affine plane) a norm
///   is convex, and the linear interpolation of a convex function over a
///   triangle of its values is at least the function. When the table holds
///   the lengths of real paths (as F* does, docs/fod.md), so does every
///   value interpolated.
/// * Between lattice directions it exceeds F by at most the interpolation
///   error of a convex function, O((1/n)^2) where F is smooth (measured for
///   FOD norms in docs/fod.md).
template <int Order>
struct LatticeTableNorm {
  static_assert(Order >= 1 && Order <= 3, "lattice orders 1 to 3 are supported");
  static constexpr int kOrder = Order;
  static constexpr int kSide = 2 * Order + 1;
  static constexpr int kCount = (kSide * kSide * kSide - (kSide - 2) * (kSide - 2) * (kSide - 2)) / 2;

  struct VertexParams {
    /// Physical vector (mm) to index offset: A^-1 = (D diag(spacing))^-1, row-major.
    float toIndex[9];
    /// C_d for the lattice offsets d in the order of latticeOffset(t).
    float cost[kCount];
  };
  using EdgeParams = VertexParams;
  static constexpr bool kEdgeRuleIsMean = true;
  /// Exact along the lattice directions only, above the norm between them
  /// (norms.hpp): STVD runs its chain of edges without any-angle ancestors
  /// or source factoring on it. Measured on constant FOD crossings, where a
  /// straight segment from the seed is no better measured than the chain's
  /// segments: the ancestors and the seed's segment lowered no error and
  /// cost 1.5 times the propagation's time (docs/accuracy.md, "FOD
  /// metrics").
  static constexpr bool kExactInEveryDirection = false;

  /// The index offset of table entry t: the lattice points d with first
  /// non-zero component positive, in the order (dk slowest, then dj, di).
  static std::array<int, 3> latticeOffset(int t) { return kLattice.offset[t]; }

  STVD_ALWAYS_INLINE static EdgeParams edgeParams(const VertexParams& a, const VertexParams& b) {
    EdgeParams e;
    for (int i = 0; i < 9; ++i) e.toIndex[i] = 0.5f * (a.toIndex[i] + b.toIndex[i]);
    for (int q = 0; q < kCount; ++q) e.cost[q] = 0.5f * (a.cost[q] + b.cost[q]);
    return e;
  }

  /// Where length() reads the table for a vector (TableLookup, norms.hpp):
  /// the floats of VertexParams at `slot` (the four table entries of the
  /// lattice square the vector's direction falls in), the direction's
  /// position (u, w) in that square and the factor m / n of its length in
  /// index space. It depends on the vector and the index transform alone,
  /// which every vertex of a grid's field holds alike; so a vector measured
  /// under many interpolated tables (STVD's samples along one segment, its
  /// screen's chain means) is looked up once and reads four values of each
  /// table instead of interpolating all of them.
  static constexpr int kLookupSlots = 4;
  struct Lookup {
    int slot[kLookupSlots];
    float u, w, scale;
  };

  // Written without branches (the face, the square's diagonal and the
  // triangle are selected, not branched on): in a batch of neighbours the
  // face changes unpredictably from one vector to the next.
  STVD_ALWAYS_INLINE static Lookup lookup(const VertexParams& g, float x, float y, float z) {
    const float* t = g.toIndex;
    const float fx = t[0] * x + t[1] * y + t[2] * z;
    const float fy = t[3] * x + t[4] * y + t[5] * z;
    const float fz = t[6] * x + t[7] * y + t[8] * z;
    const float ax = std::abs(fx), ay = std::abs(fy), az = std::abs(fz);
    // The face: the axis a of the largest component (y over x only if
    // larger, z over both), its sign made positive (F(-v) = F(v)); b < c
    // the other two axes.
    const bool onY = ay > ax;
    const float mxy = onY ? ay : ax;
    const bool onZ = az > mxy;
    const float m = onZ ? az : mxy;
    const float fa = onZ ? fz : (onY ? fy : fx);
    const float fb = onY || onZ ? fx : fy;
    const float fc = onZ ? fy : fz;
    const int face = onZ ? 2 : (onY ? 1 : 0);
    // A zero vector looks up the face's centre, with length factor 0.
    const bool some = m > 0.f;
    const float s = (fa < 0.f ? -1.f : 1.f) * (static_cast<float>(Order) / (some ? m : 1.f));
    // The point on the face, in lattice units from the face's corner -n.
    const float pb = s * fb + Order, pc = s * fc + Order;
    int ib = static_cast<int>(pb), ic = static_cast<int>(pc);
    ib = ib < 0 ? 0 : (ib > 2 * Order - 1 ? 2 * Order - 1 : ib);
    ic = ic < 0 ? 0 : (ic > 2 * Order - 1 ? 2 * Order - 1 : ic);
    float u = pb - static_cast<float>(ib), w = pc - static_cast<float>(ic);
    u = u < 0.f ? 0.f : (u > 1.f ? 1.f : u);
    w = w < 0.f ? 0.f : (w > 1.f ? 1.f : w);
    const int* corner = &kLattice.square[4 * ((face * 2 * Order + ib) * 2 * Order + ic)];
    return {{corner[0], corner[1], corner[2], corner[3]}, u, w, some ? m / static_cast<float>(Order) : 0.f};
  }

  /// The length of the looked-up vector under the table whose entries at
  /// the lookup's slots are value[0..3]: the linear interpolation over the
  /// triangle of the square that holds the point, of the square's two
  /// diagonals the one whose end values sum less.
  STVD_ALWAYS_INLINE static float lookupLength(const Lookup& q, const float (&value)[kLookupSlots]) {
    const float v00 = value[0], v10 = value[1], v01 = value[2], v11 = value[3];
    const float u = q.u, w = q.w;
    // Either side of the diagonal from 00 to 11, either side of the one
    // from 10 to 01.
    const float below = v00 + u * (v10 - v00) + w * (v11 - v10), above = v00 + w * (v01 - v00) + u * (v11 - v01);
    const float near00 = v00 + u * (v10 - v00) + w * (v01 - v00);
    const float near11 = v11 + (1.f - u) * (v01 - v11) + (1.f - w) * (v10 - v11);
    const float l = v00 + v11 <= v10 + v01 ? (u >= w ? below : above) : (u + w <= 1.f ? near00 : near11);
    return q.scale * l;
  }

  /// out[n] = the length of (x[n], y[n], z[n]) under the table
  /// weight * (a + b_n), b_n = base + offset[n] (each VertexParams as
  /// floats), for n < count: a batch of lookups. Used for a batch of
  /// neighbours: Dijkstra's edges (weight 1/2, a the relaxed vertex: the
  /// mean edge rule) and STVD's chain means.
  STVD_ALWAYS_INLINE static void lookupLengths(const VertexParams& shared, int count, const float* x, const float* y,
                                               const float* z, float weight, const float* a, const float* base,
                                               const std::int64_t* offset, float* out) {
    for (int n = 0; n < count; ++n) {
      const Lookup q = lookup(shared, x[n], y[n], z[n]);
      const float* b = base + offset[n];
      float value[kLookupSlots];
      for (int k = 0; k < kLookupSlots; ++k) value[k] = weight * (a[q.slot[k]] + b[q.slot[k]]);
      out[n] = lookupLength(q, value);
    }
  }

  /// Whether a and b look vectors up alike: the same index transform.
  static bool sameLookup(const VertexParams& a, const VertexParams& b) {
    return std::equal(a.toIndex, a.toIndex + 9, b.toIndex);
  }

  STVD_ALWAYS_INLINE static float length(const EdgeParams& g, float x, float y, float z) {
    const Lookup q = lookup(g, x, y, z);
    const float value[kLookupSlots] = {g.cost[q.slot[0] - kCostSlot], g.cost[q.slot[1] - kCostSlot],
                                       g.cost[q.slot[2] - kCostSlot], g.cost[q.slot[3] - kCostSlot]};
    return lookupLength(q, value);
  }

  static std::string invalidReason(const VertexParams& p) {
    for (float c : p.cost)
      if (!(c > 0.f) || !std::isfinite(c)) return "a tabulated length is not a positive finite number";
    for (float t : p.toIndex)
      if (!std::isfinite(t)) return "the grid's index transform is not finite";
    return {};
  }

 private:
  struct Lattice {
    std::array<int, 3> offset[kCount];
    /// Per face axis a and unit square (ib, ic) of the face p_a = +n, at
    /// 4 * ((a * 2n + ib) * 2n + ic): the table entries of its corners (ib,
    /// ic), (ib + 1, ic), (ib, ic + 1), (ib + 1, ic + 1) along the other two
    /// axes b < c, as float offsets in VertexParams (kCostSlot + entry).
    int square[3 * 2 * Order * 2 * Order * 4];
  };
  static Lattice makeLattice() {
    Lattice t{};
    short slot[kSide][kSide][kSide];
    int count = 0;
    for (int k = -Order; k <= Order; ++k)
      for (int j = -Order; j <= Order; ++j)
        for (int i = -Order; i <= Order; ++i) {
          const int top = std::max(std::abs(i), std::max(std::abs(j), std::abs(k)));
          if (top != Order) continue;
          const int first = i != 0 ? i : (j != 0 ? j : k);
          if (first < 0) continue;
          t.offset[count] = {i, j, k};
          slot[i + Order][j + Order][k + Order] = slot[Order - i][Order - j][Order - k] = static_cast<short>(count);
          ++count;
        }
    for (int a = 0; a < 3; ++a) {
      const int b = a == 0 ? 1 : 0, c = a == 2 ? 1 : 2;
      for (int ib = 0; ib < 2 * Order; ++ib)
        for (int ic = 0; ic < 2 * Order; ++ic)
          for (int n = 0; n < 4; ++n) {
            int d[3];
            d[a] = Order;
            d[b] = ib + (n & 1) - Order;
            d[c] = ic + (n >> 1) - Order;
            t.square[4 * ((a * 2 * Order + ib) * 2 * Order + ic) + n] =
                kCostSlot + slot[d[0] + Order][d[1] + Order][d[2] + Order];
          }
    }
    return t;
  }
  static inline const Lattice kLattice = makeLattice();
  // The float index of cost[0] in VertexParams.
  static constexpr int kCostSlot = 9;
  static_assert(offsetof(VertexParams, cost) == kCostSlot * sizeof(float), "cost follows the 9 floats of toIndex");
};

}  // namespace stvd
