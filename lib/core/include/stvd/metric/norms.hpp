// Norms that measure edge vectors: the extension point for metrics.
//
// A Norm type tells the propagation how long a vector is on an edge. It is a
// plain struct with static functions, so the hot loops inline it:
//
//   struct MyNorm {
//     using VertexParams = ...;  // what is stored per vertex
//     using EdgeParams = ...;    // what one edge is measured with
//     // The rule that makes an edge's norm from its two end points.
//     static EdgeParams edgeParams(const VertexParams& a, const VertexParams& b);
//     // Length of the vector (x, y, z) under the edge's norm: positive for
//     // a non-zero vector and positively homogeneous of degree 1; it need
//     // not be symmetric (F(-v) may differ from F(v)) nor come from a tensor.
//     static float length(const EdgeParams& g, float x, float y, float z);
//     // Empty when the parameters define such a norm, else why not.
//     static std::string invalidReason(const VertexParams& p);
//     // Optional: true when EdgeParams is VertexParams and edgeParams is
//     // their component-wise mean, so that edgeParams(p, p) == p. STVD's
//     // chain-mean screen and its segment samples rely on it where a norm
//     // states it (EdgeRuleIsMean below).
//     static constexpr bool kEdgeRuleIsMean = true;
//     // Optional: false when length() is exact only along some directions
//     // and above the norm between them (a lattice table's interpolation).
//     // STVD's any-angle ancestors and source factoring offer long straight
//     // segments in any direction, which pay only where such a segment is
//     // measured as exactly as a chain of short ones (ExactInEveryDirection
//     // below; docs/accuracy.md, "FOD metrics").
//     static constexpr bool kExactInEveryDirection = true;
//     // Optional (TableLookup below): a norm whose length reads a few of its
//     // parameters, chosen by the vector and by parameters that every vertex
//     // of a field holds alike, says which, so that callers who measure one
//     // vector under many interpolated parameter sets interpolate only those:
//     //   static constexpr int kLookupSlots = ...;
//     //   struct Lookup { int slot[kLookupSlots]; ... };  // float offsets in VertexParams
//     //   static Lookup lookup(const VertexParams& any, float x, float y, float z);
//     //   static float lookupLength(const Lookup&, const float (&value)[kLookupSlots]);
//     //   static bool sameLookup(const VertexParams& a, const VertexParams& b);
//     // with length(g, v) == lookupLength(lookup(g, v), g's floats at the slots).
//   };
//
// RiemannianNorm and RandersNorm below are the two built in. The
// propagation is compiled for both in the library; a new norm is used by
// including "stvd/propagation/propagation_definition.hpp" (see docs/architecture.md).
#pragma once

#include <algorithm>
#include <cmath>
#include <string>
#include <type_traits>

#include "stvd/types.hpp"

namespace stvd {

/// ||v||_G = sqrt(v^T G v) for a symmetric positive-definite G.
///
/// Edge rule: an edge is measured with the arithmetic mean of the tensors at
/// its two end points, G_e = (G_a + G_b) / 2. It is exact for a constant
/// field and second-order accurate at the edge midpoint for a smooth one.
struct RiemannianNorm {
  using VertexParams = SymTensor3;
  using EdgeParams = SymTensor3;
  static constexpr bool kEdgeRuleIsMean = true;

  STVD_ALWAYS_INLINE static EdgeParams edgeParams(const VertexParams& a, const VertexParams& b) {
    return {0.5f * (a.xx + b.xx), 0.5f * (a.xy + b.xy), 0.5f * (a.xz + b.xz),
            0.5f * (a.yy + b.yy), 0.5f * (a.yz + b.yz), 0.5f * (a.zz + b.zz)};
  }
  STVD_ALWAYS_INLINE static float length(const EdgeParams& g, float x, float y, float z) {
    // Products of the vector's components first: when one vector is
    // measured with many edge norms (the STVD chain), they are computed once.
    const float q = g.xx * (x * x) + g.yy * (y * y) + g.zz * (z * z) +
                    g.xy * (2.f * x * y) + g.xz * (2.f * x * z) + g.yz * (2.f * y * z);
    return std::sqrt(std::max(q, 0.f));
  }
  static std::string invalidReason(const VertexParams& g);
};

/// The Randers norm F(v) = sqrt(v^T M v) + omega^T v: a Riemannian part and
/// a drift term, the simplest asymmetric (non-Riemannian) norm. It is a
/// norm, i.e. F(v) > 0 for v != 0, exactly when omega^T M^-1 omega < 1.
/// Going along omega costs more, going against it less (Zermelo navigation).
///
/// Edge rule: mean of M and mean of omega of the two end points.
struct RandersNorm {
  struct VertexParams {
    SymTensor3 m;
    Vec3f omega;
  };
  using EdgeParams = VertexParams;
  static constexpr bool kEdgeRuleIsMean = true;

  STVD_ALWAYS_INLINE static EdgeParams edgeParams(const VertexParams& a, const VertexParams& b) {
    return {RiemannianNorm::edgeParams(a.m, b.m),
            {0.5f * (a.omega.x + b.omega.x), 0.5f * (a.omega.y + b.omega.y),
             0.5f * (a.omega.z + b.omega.z)}};
  }
  STVD_ALWAYS_INLINE static float length(const EdgeParams& g, float x, float y, float z) {
    const float f = RiemannianNorm::length(g.m, x, y, z) +
                    (g.omega.x * x + g.omega.y * y + g.omega.z * z);
    return std::max(f, 0.f);
  }
  static std::string invalidReason(const VertexParams& p);
};

/// Empty when g is symmetric positive definite with finite entries (checked
/// by a Cholesky factorisation in double precision), otherwise the reason.
std::string spdViolation(const SymTensor3& g);

/// Norm::kEdgeRuleIsMean where the norm states it, else false.
template <class Norm, class = void>
struct EdgeRuleIsMean : std::false_type {};
template <class Norm>
struct EdgeRuleIsMean<Norm, std::void_t<decltype(Norm::kEdgeRuleIsMean)>>
    : std::bool_constant<Norm::kEdgeRuleIsMean> {};

/// Norm::kExactInEveryDirection where the norm states it, else true.
template <class Norm, class = void>
struct ExactInEveryDirection : std::true_type {};
template <class Norm>
struct ExactInEveryDirection<Norm, std::void_t<decltype(Norm::kExactInEveryDirection)>>
    : std::bool_constant<Norm::kExactInEveryDirection> {};

/// Whether Norm offers the lookup of its length's parameters (above).
template <class Norm, class = void>
struct TableLookup : std::false_type {};
template <class Norm>
struct TableLookup<Norm, std::void_t<decltype(Norm::kLookupSlots), typename Norm::Lookup>> : std::true_type {};

}  // namespace stvd
