// An explicit mesh in 3D: vertices with positions and a compressed sparse
// row (CSR) adjacency built from the edges of its cells.
#pragma once

#include <array>
#include <cstdint>
#include <optional>
#include <vector>

#include "stvd/cell_mesh/tetrahedral_region.hpp"
#include "stvd/detail/compiler.hpp"
#include "stvd/types.hpp"

namespace stvd {

/// A volumetric mesh seen as a graph: its vertices and the edges of its
/// cells (tetrahedra, hexahedra, general polyhedra). Edge vectors are the
/// physical displacements between vertex positions, computed on the fly.
///
/// A mesh built from tetrahedra also keeps them as a TetrahedralRegion, so
/// that an STVD candidate's straight segment can be walked through them:
/// refused where it leaves the mesh, measured along itself where it does
/// not (cell_mesh_candidate_path.hpp). Meshes built from other cells or
/// from edges are graphs only: every candidate is taken, and
/// ChainMeasure::Segment falls back to ChainMeasure::LargestEdgeNorm.
class CellMeshDomain {
 public:
  using Tetrahedron = std::array<VertexId, 4>;
  /// A polyhedral cell given by its faces, each a closed polygon of vertex
  /// indices (consecutive vertices, and the last and first, share an edge).
  using PolyhedralCell = std::vector<std::vector<VertexId>>;

  /// The six edges of every tetrahedron, and the tetrahedra themselves
  /// (tetrahedra()). Throws std::invalid_argument for an index out of range,
  /// a tetrahedron with a repeated vertex, or a face shared by more than two
  /// tetrahedra.
  static CellMeshDomain fromTetrahedra(std::vector<Vec3d> points,
                                       const std::vector<Tetrahedron>& tets);
  /// The edges of the faces of every cell.
  static CellMeshDomain fromPolyhedra(std::vector<Vec3d> points,
                                      const std::vector<PolyhedralCell>& cells);
  /// An explicit undirected edge list (each pair once or twice, in any order).
  static CellMeshDomain fromEdges(std::vector<Vec3d> points,
                                  std::vector<std::array<VertexId, 2>> edges);

  VertexId vertexCount() const { return static_cast<VertexId>(points_.size()); }
  VertexId domainVertexCount() const { return vertexCount(); }
  bool contains(VertexId v) const { return v < vertexCount(); }
  std::size_t edgeCount() const { return neighbors_.size() / 2; }
  const std::vector<Vec3d>& points() const { return points_; }
  /// The tetrahedra of a mesh built by fromTetrahedra, else null.
  const TetrahedralRegion* tetrahedra() const { return region_ ? &*region_ : nullptr; }
  Vec3d physicalPoint(VertexId v) const { return points_[v]; }
  Vec3f displacement(VertexId from, VertexId to) const {
    return toFloat(points_[to] - points_[from]);
  }
  /// Neighbours of v in increasing index order.
  const VertexId* neighborsBegin(VertexId v) const { return neighbors_.data() + firstNeighbor_[v]; }
  const VertexId* neighborsEnd(VertexId v) const { return neighbors_.data() + firstNeighbor_[v + 1]; }

  /// Calls f(w, w) for every neighbour w of v: the runs of consecutive
  /// vertex numbers that hold v's neighbours (as
  /// VoxelGridDomain::forEachNeighborRun), on a mesh one vertex each.
  template <class F>
  STVD_ALWAYS_INLINE void forEachNeighborRun(VertexId v, F&& f) const {
    for (const VertexId* it = neighborsBegin(v); it != neighborsEnd(v); ++it) f(*it, *it);
  }
  /// Asks for the positions of v's neighbours, which forEachNeighbor reads
  /// to form the edge vectors (a prefetch: only the caches change).
  STVD_ALWAYS_INLINE void prefetchNeighborGeometry(VertexId v) const {
    for (const VertexId* it = neighborsBegin(v); it != neighborsEnd(v); ++it)
      detail::prefetchRange(&points_[*it], &points_[*it]);
  }

  /// Calls f(w, e) for every neighbour w of v with e = x(w) - x(v).
  template <class F>
  STVD_ALWAYS_INLINE void forEachNeighbor(VertexId v, F&& f) const {
    const Vec3d p = points_[v];
    for (const VertexId* it = neighborsBegin(v); it != neighborsEnd(v); ++it) {
      f(*it, toFloat(points_[*it] - p));
    }
  }

 private:
  CellMeshDomain(std::vector<Vec3d> points, std::vector<std::array<VertexId, 2>> edges);
  std::vector<Vec3d> points_;
  std::vector<std::uint64_t> firstNeighbor_;  // CSR row starts, vertexCount + 1 entries
  std::vector<VertexId> neighbors_;
  std::optional<TetrahedralRegion> region_;
};

}  // namespace stvd
