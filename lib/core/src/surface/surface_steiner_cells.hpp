// The Steiner-point layout over the faces of a polygon surface (private to
// the library): it numbers the points of Lanthier's graph and, for a point
// u, hands every face around u to Lanthier's Dijkstra as a SteinerCellView
// (lanthier/lanthier_dijkstra.hpp).
#pragma once

#include <array>
#include <cstdint>
#include <vector>

#include "lanthier/lanthier_dijkstra.hpp"
#include "stvd/surface/surface_domain.hpp"

namespace stvd::detail {

/// Faces of a polygon surface, each one cell (polygons are not
/// triangulated); see steinerPointPosition for the numbering. Built once from
/// the surface's faces: the undirected edges, each face's edge per side, the
/// faces on each edge (one or two) and the faces around each vertex.
class SurfaceSteinerCells {
 public:
  /// The numbering and positions.
  SurfaceSteinerCells(const SurfaceDomain& surface, int steinerPoints);
  /// The same for a propagation, reporting setupSteps(surface) steps to
  /// `setup` (one per face or vertex of each pass).
  SurfaceSteinerCells(const SurfaceDomain& surface, int steinerPoints, SetupProgress& setup);
  static std::uint64_t setupSteps(const SurfaceDomain& surface);

  std::uint64_t pointCount() const { return pointCount_; }
  SteinerPointId pointOfVertex(VertexId v) const { return v; }
  VertexId vertexOfPoint(SteinerPointId p) const { return p < surface_.vertexCount() ? p : kNoVertex; }
  Vec3d position(SteinerPointId p) const;
  int maxCellPoints() const { return static_cast<int>(position_.size()); }
  int maxCellCorners() const { return maxCorners_; }
  /// The undirected edges, each (smaller vertex, larger vertex), sorted.
  const std::vector<std::array<VertexId, 2>>& edges() const { return edges_; }

  template <class F>
  void forEachCellAround(SteinerPointId u, F&& f) {
    const std::uint32_t* begin;
    const std::uint32_t* end;
    if (u < surface_.vertexCount()) {
      begin = vertexFace_.data() + vertexFaceStart_[u];
      end = vertexFace_.data() + vertexFaceStart_[u + 1];
    } else {
      const std::uint32_t e = (u - surface_.vertexCount()) / m_;
      begin = edgeFace_[e].data();
      end = begin + (edgeFace_[e][1] == kNoFace ? 1 : 2);
    }
    const Vec3d self = position(u);
    const PolygonList& faces = surface_.faces();
    for (const std::uint32_t* face = begin; face != end; ++face) {
      const int n = gather(*face);
      const std::uint32_t first = faces.faceStart[*face];
      f(SteinerCellView{faces.faceVertex.data() + first,
                        static_cast<int>(faces.faceStart[*face + 1] - first), n, 0, id_.data(),
                        position_.data(), toFloat(self - surface_.points()[faces.faceVertex[first]])});
    }
  }

 private:
  static constexpr std::uint32_t kNoFace = 0xffffffffu;
  SurfaceSteinerCells(const SurfaceDomain& surface, int steinerPoints, SetupProgress* setup);
  int gather(std::uint32_t f);  // fills id_ and position_ for face f, returns the point count

  const SurfaceDomain& surface_;
  int m_;
  int maxCorners_ = 0;
  std::uint64_t pointCount_;
  std::vector<std::array<VertexId, 2>> edges_;
  std::vector<std::uint32_t> sideEdge_;                 // per face corner: the edge to the next corner
  std::vector<std::array<std::uint32_t, 2>> edgeFace_;  // per edge: its faces (kNoFace on a boundary)
  std::vector<std::uint32_t> vertexFaceStart_, vertexFace_;
  std::vector<SteinerPointId> id_;
  std::vector<Vec3f> position_;
};

}  // namespace stvd::detail
