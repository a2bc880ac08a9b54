// How STVD places a predecessor chain on a surface: unfolded edge by edge
// into the tangent frame of the vertex just finalised (paper, section 6), and
// each edge's norm carried into that frame (propagation/chain_unfolding.hpp
// describes the interface; VolumeChainUnfolding is the one of domains in R^3).
#pragma once

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <type_traits>
#include <vector>

#include "stvd/metric/metric_field.hpp"
#include "stvd/metric/norms.hpp"
#include "stvd/propagation/propagation.hpp"
#include "stvd/surface/surface_domain.hpp"
#include "stvd/types.hpp"

namespace stvd {

/// The STVD chain on a surface: unfolded edge by edge into v's frame. At
/// chain vertex c_i the next edge leaves at the angle, relative to the edge
/// back to c_{i-1}, that the two have in c_i's own (scaled) frame, with the
/// edge's 3D length; so edge lengths and relative 1-ring angles are kept
/// (paper, figure 8). Nothing of the surface's embedding beyond lengths and
/// corner angles is used.
struct SurfaceChainUnfolding {
  /// Edge norms are carried into the unfolded frame, not plain means.
  static constexpr bool kEdgeNormIsMean = false;
  /// The edge v -> w in v's frame, as forEachNeighbor(v, ...) reports it.
  static Vec3f neighborEdge(const SurfaceDomain& domain, VertexId v, VertexId w) {
    const std::uint32_t i = domain.ringIndex(v, w);
    return Vec3f{domain.ringEdgeX(i), domain.ringEdgeY(i), 0.f};
  }
  static void place(const SurfaceDomain& domain, const VertexId* chain, int count, Vec3f* p) {
    p[0] = Vec3f{};
    if (count < 2) return;
    // Directions are unit complex numbers (x, y); turning by the angle
    // between two ring entries is a product, so no trigonometry is needed.
    const std::uint32_t first = domain.ringIndex(chain[0], chain[1]);
    double x = domain.ringEdgeX(first), y = domain.ringEdgeY(first);
    p[1] = Vec3f{static_cast<float>(x), static_cast<float>(y), 0.f};
    // Direction (in the common frame) of the edge from c_i back to c_{i-1}.
    double backX = -domain.ringDirectionX(first), backY = -domain.ringDirectionY(first);
    for (int i = 1; i + 1 < count; ++i) {
      const std::uint32_t toPrevious = domain.ringIndex(chain[i], chain[i - 1]);
      const std::uint32_t toNext = domain.ringIndex(chain[i], chain[i + 1]);
      // The turn from the edge back to c_{i-1} to the edge on to c_{i+1}
      // in c_i's frame: conj(previous) * next.
      const double ax = domain.ringDirectionX(toPrevious), ay = domain.ringDirectionY(toPrevious);
      const double bx = domain.ringDirectionX(toNext), by = domain.ringDirectionY(toNext);
      const double turnX = ax * bx + ay * by, turnY = ax * by - ay * bx;
      const double dx = backX * turnX - backY * turnY, dy = backX * turnY + backY * turnX;
      const double length = domain.ringLength(toNext);
      x += length * dx;
      y += length * dy;
      p[i + 1] = Vec3f{static_cast<float>(x), static_cast<float>(y), 0.f};
      backX = -dx;
      backY = -dy;
    }
  }

  /// The tensor of each edge in its own frame (SurfaceDomain::edgeTensors),
  /// made once per propagation: Dijkstra and the segment measure take the
  /// cheaper face's, so that no edge undercuts a path through a face under
  /// the face-wise metric; the chain rules keep the paper's mean of the end
  /// points (their documented figures).
  struct EdgeMetric {
    std::vector<float> tensor;  // {dd, dp, pp} per ring entry
  };
  template <class Norm>
  static EdgeMetric edgeMetric(const SurfaceDomain& domain, const MetricField<Norm>& metric,
                               const PropagationOptions& options) {
    static_assert(std::is_same_v<Norm, RiemannianNorm>,
                  "surfaces are measured with RiemannianNorm (world tensors per vertex)");
    const bool faceWise =
        options.method == Method::Dijkstra || options.chainMeasure == ChainMeasure::Segment;
    return {domain.edgeTensors(metric, faceWise ? SurfaceDomain::EdgeTensorRule::CheaperFace
                                                : SurfaceDomain::EdgeTensorRule::EndpointMean)};
  }

  /// The edge's tensor in the frame where the edge is `e`: its tensor in its
  /// own frame (edgeMetric), turned so that the edge direction becomes
  /// e / |e|. Only the xx, xy, yy entries are set (vectors in the frame have
  /// z = 0).
  template <class Norm>
  static SymTensor3 edgeNorm(const SurfaceDomain& domain, const EdgeMetric& edges, const SymTensor3&,
                             const SymTensor3&, VertexId a, VertexId b, Vec3f e) {
    static_assert(std::is_same_v<Norm, RiemannianNorm>,
                  "surfaces are measured with RiemannianNorm (world tensors per vertex)");
    const float* t = &edges.tensor[3 * std::size_t(domain.ringIndex(a, b))];
    const float dd = t[0], dp = t[1], pp = t[2];
    const float inv = 1.f / std::sqrt(std::max(e.x * e.x + e.y * e.y, 1e-30f));
    const float ux = e.x * inv, uy = e.y * inv;  // edge direction
    const float wx = -uy, wy = ux;               // its left normal in the frame
    SymTensor3 m;
    m.xx = dd * ux * ux + 2.f * dp * ux * wx + pp * wx * wx;
    m.yy = dd * uy * uy + 2.f * dp * uy * wy + pp * wy * wy;
    m.xy = dd * ux * uy + dp * (ux * wy + wx * uy) + pp * wx * wy;
    return m;
  }
};

}  // namespace stvd
