// A tetrahedral mesh with its cells kept: the edges and faces of the
// tetrahedra and which tetrahedra meet at each vertex, edge and face. It is
// what cell-based methods (Steiner-point propagation) need and what
// CellMeshDomain, an edge graph, does not store.
#pragma once

#include <array>
#include <cstdint>
#include <vector>

#include "stvd/types.hpp"

namespace stvd {

class TetrahedralCells {
 public:
  using Tetrahedron = std::array<VertexId, 4>;
  /// Vertex indices in increasing order.
  using Edge = std::array<VertexId, 2>;
  using Face = std::array<VertexId, 3>;

  /// Throws std::invalid_argument for an index out of range, a tetrahedron
  /// with a repeated vertex, no tetrahedron, or more than 2^32 - 2 points.
  TetrahedralCells(std::vector<Vec3d> points, std::vector<Tetrahedron> tets);

  VertexId vertexCount() const { return static_cast<VertexId>(points_.size()); }
  bool contains(VertexId v) const { return v < vertexCount(); }
  const std::vector<Vec3d>& points() const { return points_; }
  const std::vector<Tetrahedron>& tets() const { return tets_; }
  const std::vector<Edge>& edges() const { return edges_; }
  const std::vector<Face>& faces() const { return faces_; }

  /// Edge indices of tetrahedron t, in the order of its vertex pairs
  /// (0,1) (0,2) (0,3) (1,2) (1,3) (2,3).
  const std::array<std::uint32_t, 6>& tetEdges(std::size_t t) const { return tetEdges_[t]; }
  /// Face indices of tetrahedron t; face f is opposite vertex f.
  const std::array<std::uint32_t, 4>& tetFaces(std::size_t t) const { return tetFaces_[t]; }

  /// Tetrahedra around a vertex / an edge / a face (one or two).
  const std::uint32_t* vertexTetsBegin(VertexId v) const { return vertexTets_.data() + vertexFirst_[v]; }
  const std::uint32_t* vertexTetsEnd(VertexId v) const { return vertexTets_.data() + vertexFirst_[v + 1]; }
  const std::uint32_t* edgeTetsBegin(std::uint32_t e) const { return edgeTets_.data() + edgeFirst_[e]; }
  const std::uint32_t* edgeTetsEnd(std::uint32_t e) const { return edgeTets_.data() + edgeFirst_[e + 1]; }
  const std::uint32_t* faceTetsBegin(std::uint32_t f) const { return faceTets_.data() + 2 * f; }
  const std::uint32_t* faceTetsEnd(std::uint32_t f) const {
    return faceTets_.data() + 2 * f + (faceTets_[2 * f + 1] == kNone ? 1 : 2);
  }

 private:
  static constexpr std::uint32_t kNone = 0xffffffffu;
  std::vector<Vec3d> points_;
  std::vector<Tetrahedron> tets_;
  std::vector<Edge> edges_;
  std::vector<Face> faces_;
  std::vector<std::array<std::uint32_t, 6>> tetEdges_;
  std::vector<std::array<std::uint32_t, 4>> tetFaces_;
  std::vector<std::uint64_t> vertexFirst_, edgeFirst_;
  std::vector<std::uint32_t> vertexTets_, edgeTets_, faceTets_;
};

}  // namespace stvd
