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

#include "stvd/detail/compiler.hpp"
#include "stvd/errors.hpp"
#include "stvd/metric/metric_field.hpp"
#include "stvd/types.hpp"

namespace stvd {

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
  /// Unit normal of face f (Newell's method), on the side around which its
  /// vertices run counter-clockwise; zero for a face without area.
  const Vec3d& faceNormal(std::size_t f) const { return faceNormals_[f]; }
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
  /// Ring entry i as a walk across the faces around v reads it: the
  /// neighbour and the edge's length, and the face between entry i and the
  /// next one counter-clockwise with its corner angle at v as it is on the
  /// surface (not scaled to a full turn), as cosine and sine, so that
  /// turning by it is one complex product. The last entry of a boundary fan
  /// has no face after it (kNoFace, angle 0). The true angles unfold faces
  /// isometrically, as the STVD candidates' paths need them
  /// (SurfaceCandidatePath); one record per entry, so that a
  /// fan is read from one or two cache lines.
  struct RingCorner {
    double cos, sin, length;
    VertexId neighbor;
    std::uint32_t face;
  };
  const RingCorner& ringCorner(std::uint32_t i) const { return ringCorner_[i]; }
  std::uint32_t ringFace(std::uint32_t i) const { return ringCorner_[i].face; }
  /// The face before ring entry i (between the previous entry and i, around
  /// the ring): with ringFace(i), the two faces of the edge to entry i;
  /// kNoFace at the start of a boundary fan.
  std::uint32_t ringFaceBefore(VertexId v, std::uint32_t i) const {
    return ringCorner_[i > ringStart_[v] ? i - 1 : ringStart_[v + 1] - 1].face;
  }
  static constexpr std::uint32_t kNoFace = 0xffffffffu;

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

  /// Per face (in faces() order), the mean of its corners' tensors: the
  /// face-wise metric that Lanthier's method uses, with which a path
  /// inside a face is measured.
  std::vector<SymTensor3> faceTensors(const RiemannianMetric& metric) const;

  /// Which tensor measures an edge.
  enum class EdgeTensorRule {
    /// The mean of the end points' tensors (the paper's per-edge norm).
    EndpointMean,
    /// The tensor of the edge's cheaper face, the one that measures the
    /// edge shorter: the edge is a path in either face, so under the
    /// face-wise metric its length is the smaller of the two, and no edge
    /// undercuts a path through a face.
    CheaperFace,
  };

  /// Per ring entry (v, w), three floats {dd, dp, pp}: the edge's tensor
  /// restricted to the edge's own frame (d, n_e x d), d the unit edge
  /// direction and n_e the mean normal of the two end points. Reversing the
  /// edge flips both axes, which leaves the tensor unchanged: an edge has
  /// one tensor, whichever way it is walked.
  std::vector<float> edgeTensors(const RiemannianMetric& metric, EdgeTensorRule rule) const;

 private:
  std::vector<Vec3d> points_;
  PolygonList faces_;
  std::vector<Vec3d> normals_, tangents_;
  std::vector<Vec3d> faceNormals_;
  std::vector<double> angleSum_;
  std::vector<std::uint8_t> boundary_;
  std::vector<std::uint32_t> component_;
  std::uint32_t componentCount_ = 0;
  std::vector<std::uint32_t> ringStart_;
  std::vector<VertexId> ringNeighbor_;
  std::vector<float> ringAngle_, ringEdgeX_, ringEdgeY_;
  std::vector<double> ringLength_, ringDirectionX_, ringDirectionY_;
  std::vector<RingCorner> ringCorner_;
};

}  // namespace stvd
