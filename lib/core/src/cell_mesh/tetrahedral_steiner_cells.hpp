// The Steiner-point layout over the tetrahedra of a mesh (private to the
// library): it numbers the points of Lanthier's graph and, for a point u,
// hands every tetrahedron around u to Lanthier's Dijkstra as a
// SteinerCellView (lanthier/lanthier_dijkstra.hpp).
#pragma once

#include <array>
#include <cstdint>
#include <vector>

#include "lanthier/lanthier_dijkstra.hpp"
#include "stvd/cell_mesh/tetrahedral_cells.hpp"

namespace stvd::detail {

/// Tetrahedra; see steinerPointPosition for the numbering.
class TetSteinerCells {
 public:
  TetSteinerCells(const TetrahedralCells& cells, int steinerPoints);
  /// For a propagation: no steps of `setup` (the mesh's edges and faces are
  /// the TetrahedralCells' own).
  TetSteinerCells(const TetrahedralCells& cells, int steinerPoints, SetupProgress& setup)
      : TetSteinerCells(cells, steinerPoints) {
    (void)setup;
  }

  std::uint64_t pointCount() const { return pointCount_; }
  SteinerPointId pointOfVertex(VertexId v) const { return v; }
  VertexId vertexOfPoint(SteinerPointId p) const { return p < cells_.vertexCount() ? p : kNoVertex; }
  Vec3d position(SteinerPointId p) const;
  int maxCellPoints() const { return static_cast<int>(position_.size()); }
  int maxCellCorners() const { return 4; }

  template <class F>
  void forEachCellAround(SteinerPointId u, F&& f) {
    const std::uint32_t* begin;
    const std::uint32_t* end;
    if (u < cells_.vertexCount()) {
      begin = cells_.vertexTetsBegin(u);
      end = cells_.vertexTetsEnd(u);
    } else if (u < firstFacePoint_) {
      const std::uint32_t e = (u - cells_.vertexCount()) / m_;
      begin = cells_.edgeTetsBegin(e);
      end = cells_.edgeTetsEnd(e);
    } else {
      const std::uint32_t f = (u - firstFacePoint_) / facePoints_;
      begin = cells_.faceTetsBegin(f);
      end = cells_.faceTetsEnd(f);
    }
    const Vec3d self = position(u);
    for (const std::uint32_t* t = begin; t != end; ++t) {
      gather(*t);
      f(SteinerCellView{cells_.tets()[*t].data(), 4, static_cast<int>(position_.size()), 0, id_.data(),
                        position_.data(), toFloat(self - cells_.points()[cells_.tets()[*t][0]])});
    }
  }

 private:
  void gather(std::uint32_t t);  // fills id_ and position_ for tetrahedron t

  const TetrahedralCells& cells_;
  int m_;
  std::uint32_t facePoints_;  // M (M - 1) / 2
  std::uint64_t firstFacePoint_, pointCount_;
  std::vector<std::array<double, 2>> faceLattice_;  // (b, c) / (M + 1) per face point
  std::vector<SteinerPointId> id_;
  std::vector<Vec3f> position_;
};

}  // namespace stvd::detail
