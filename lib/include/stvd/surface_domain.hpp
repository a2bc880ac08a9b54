// A 2-manifold polygon surface (triangles, quads, general polygons) as a
// propagation domain: the surface half of the adjacency core (paper,
// sections 3 and 6). See docs/surfaces.md.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <stdexcept>
#include <initializer_list>
#include <string>
#include <type_traits>
#include <vector>

#include "stvd/chain_unfolding.hpp"
#include "stvd/metric_field.hpp"
#include "stvd/norms.hpp"
#include "stvd/propagation.hpp"
#include "stvd/types.hpp"

namespace stvd {

/// Input that is not an orientable 2-manifold polygon surface (an index out
/// of range, a face with fewer than 3 or repeated vertices, an edge shared
/// by more than two faces, a vertex whose faces form several fans, a
/// non-orientable surface). what() names the face, edge or vertex.
class SurfaceError : public std::invalid_argument {
 public:
  using std::invalid_argument::invalid_argument;
};

/// Faces as polygons: `faceStart` has faceCount + 1 entries and face f is
/// `faceVertex[faceStart[f] .. faceStart[f + 1])`, in order around the face.
struct PolygonList {
  std::vector<std::uint32_t> faceStart{0};
  std::vector<VertexId> faceVertex;

  std::size_t faceCount() const { return faceStart.size() - 1; }
  void add(std::initializer_list<VertexId> face) {
    faceVertex.insert(faceVertex.end(), face.begin(), face.end());
    faceStart.push_back(static_cast<std::uint32_t>(faceVertex.size()));
  }
  template <class It>
  void add(It begin, It end) {
    faceVertex.insert(faceVertex.end(), begin, end);
    faceStart.push_back(static_cast<std::uint32_t>(faceVertex.size()));
  }
};

/// An orientable 2-manifold polygon surface, possibly with boundaries and
/// several components.
///
/// Each vertex v has a 2D frame in its tangent plane: its 1-ring neighbours
/// (the edge neighbours in its faces: no polygon diagonals) lie at angles
/// that start at 0 for the first neighbour and grow counter-clockwise around
/// the outward side (the side from which the faces, as oriented, run
/// counter-clockwise) by the faces' corner angles at v. At an interior
/// vertex the corner angles are scaled so that they sum to 2 pi (the
/// relative 1-ring angles are kept); at a boundary vertex they are kept as
/// they are. forEachNeighbor reports the edge v -> w in that frame as
/// (x, y, 0) with the edge's 3D length.
///
/// Faces are re-oriented consistently per component when the input mixes
/// orientations; a non-orientable component is rejected.
class SurfaceDomain {
 public:
  /// Throws SurfaceError for input that is not an orientable 2-manifold.
  SurfaceDomain(std::vector<Vec3d> points, const PolygonList& faces);

  VertexId vertexCount() const { return static_cast<VertexId>(points_.size()); }
  VertexId domainVertexCount() const { return vertexCount(); }
  bool contains(VertexId v) const { return v < vertexCount(); }
  std::size_t faceCount() const { return faces_.faceCount(); }
  std::size_t edgeCount() const { return ringNeighbor_.size() / 2; }
  /// The faces as used (re-oriented where the input was inconsistent).
  const PolygonList& faces() const { return faces_; }
  const std::vector<Vec3d>& points() const { return points_; }
  Vec3d physicalPoint(VertexId v) const { return points_[v]; }
  /// Unit normal at v: the corner-angle weighted mean of its face normals.
  Vec3d normal(VertexId v) const { return normals_[v]; }
  /// Unit tangent t1 of v's frame (the direction of its first neighbour,
  /// projected into the tangent plane); t2 = normal x t1. For an isolated
  /// vertex any unit vector orthogonal to the normal.
  Vec3d tangent(VertexId v) const { return tangents_[v]; }
  bool isBoundary(VertexId v) const { return boundary_[v] != 0; }
  /// Sum of the corner angles at v before scaling (2 pi on a flat interior).
  double angleSum(VertexId v) const { return angleSum_[v]; }
  /// Component index per vertex (connected through edges), and their count.
  const std::vector<std::uint32_t>& component() const { return component_; }
  std::uint32_t componentCount() const { return componentCount_; }

  /// 1-ring of v, counter-clockwise, with each neighbour's angle in v's frame.
  std::uint32_t ringBegin(VertexId v) const { return ringStart_[v]; }
  std::uint32_t ringEnd(VertexId v) const { return ringStart_[v + 1]; }
  VertexId ringNeighbor(std::uint32_t i) const { return ringNeighbor_[i]; }
  float ringAngle(std::uint32_t i) const { return ringAngle_[i]; }
  /// The edge to ring entry i in v's frame, its length and unit direction.
  float ringEdgeX(std::uint32_t i) const { return ringEdgeX_[i]; }
  float ringEdgeY(std::uint32_t i) const { return ringEdgeY_[i]; }
  double ringLength(std::uint32_t i) const { return ringLength_[i]; }
  double ringDirectionX(std::uint32_t i) const { return ringDirectionX_[i]; }
  double ringDirectionY(std::uint32_t i) const { return ringDirectionY_[i]; }
  /// Index of w in v's ring; throws std::logic_error when w is no neighbour.
  std::uint32_t ringIndex(VertexId v, VertexId w) const {
    for (std::uint32_t i = ringStart_[v]; i < ringStart_[v + 1]; ++i)
      if (ringNeighbor_[i] == w) return i;
    throw std::logic_error("vertex " + std::to_string(w) + " is not a neighbour of vertex " +
                           std::to_string(v));
  }

  /// Calls f(w, e) for every neighbour w of v with e the edge in v's frame.
  template <class F>
  STVD_ALWAYS_INLINE void forEachNeighbor(VertexId v, F&& f) const {
    for (std::uint32_t i = ringStart_[v]; i < ringStart_[v + 1]; ++i)
      f(ringNeighbor_[i], Vec3f{ringEdgeX_[i], ringEdgeY_[i], 0.f});
  }

  /// A world-space tensor restricted to the edge from -> to: the 2x2 tensor
  /// in the edge's own frame (d, n_e x d), d the unit edge direction and
  /// n_e the mean normal of the two end points, returned as {dd, dp, pp}.
  /// Reversing the edge flips both axes, which leaves the tensor unchanged:
  /// an edge has one tensor, whichever way it is walked.
  /// Single precision and inline: it runs for every measured edge.
  STVD_ALWAYS_INLINE void edgeFrameTensor(const SymTensor3& g, VertexId from, VertexId to,
                                          float& dd, float& dp, float& pp) const {
    auto unit = [](Vec3f v) {
      const float n2 = dot(v, v);
      return n2 > 0.f ? (1.f / std::sqrt(n2)) * v : Vec3f{};
    };
    const Vec3f d = unit(toFloat(points_[to] - points_[from]));
    const Vec3f nE = unit(unitNormals_[from] + unitNormals_[to]);
    const Vec3f p = unit(Vec3f{nE.y * d.z - nE.z * d.y, nE.z * d.x - nE.x * d.z,
                               nE.x * d.y - nE.y * d.x});
    const Vec3f gd = g.apply(d);
    dd = dot(d, gd);
    dp = dot(p, gd);
    pp = g.quadraticForm(p);
  }

 private:
  std::vector<Vec3d> points_;
  PolygonList faces_;
  std::vector<Vec3d> normals_, tangents_;
  std::vector<double> angleSum_;
  std::vector<std::uint8_t> boundary_;
  std::vector<std::uint32_t> component_;
  std::uint32_t componentCount_ = 0;
  std::vector<std::uint32_t> ringStart_;
  std::vector<VertexId> ringNeighbor_;
  std::vector<float> ringAngle_, ringEdgeX_, ringEdgeY_;
  std::vector<double> ringLength_, ringDirectionX_, ringDirectionY_;
  std::vector<Vec3f> unitNormals_;  // normals_ in single precision, for edgeFrameTensor
};

/// The STVD chain on a surface: unfolded edge by edge into v's frame. At
/// chain vertex c_i the next edge leaves at the angle, relative to the edge
/// back to c_{i-1}, that the two have in c_i's own (scaled) frame, with the
/// edge's 3D length; so edge lengths and relative 1-ring angles are kept
/// (paper, figure 8). Nothing of the surface's embedding beyond lengths and
/// corner angles is used.
template <>
struct ChainUnfolding<SurfaceDomain> {
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

  /// The edge's tensor in the frame where the edge is `e`: the metric of the
  /// two end points (world tensors, their mean) restricted to the edge's own
  /// frame, then turned so that the edge direction becomes e / |e|. Only the
  /// xx, xy, yy entries are set (vectors in the frame have z = 0).
  template <class Norm>
  static SymTensor3 edgeNorm(const SurfaceDomain& domain, const SymTensor3& from,
                             const SymTensor3& to, VertexId a, VertexId b, Vec3f e) {
    static_assert(std::is_same_v<Norm, RiemannianNorm>,
                  "surfaces are measured with RiemannianNorm (world tensors per vertex)");
    float dd, dp, pp;
    domain.edgeFrameTensor(RiemannianNorm::edgeParams(from, to), a, b, dd, dp, pp);
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

extern template PropagationResult propagate(const SurfaceDomain&, const RiemannianMetric&,
                                            const std::vector<VertexId>&,
                                            const PropagationOptions&);

}  // namespace stvd
