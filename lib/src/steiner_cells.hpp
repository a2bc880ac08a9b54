// The Steiner-point layouts over the cell structures (private to the
// library). Each class numbers the points of its Steiner graph and, for a
// point u, hands every cell around u to a callback as a SteinerCellView: the
// cell's corner vertices (for its norm) and all points on its boundary
// (ids and positions).
#pragma once

#include <array>
#include <cstdint>
#include <vector>

#include "stvd/steiner_propagation.hpp"
#include "stvd/surface_domain.hpp"
#include "stvd/tetrahedral_cells.hpp"
#include "stvd/voxel_grid_domain.hpp"

namespace stvd::detail {

/// The boundary points of one cell, seen from one of them (`self`).
/// Positions are relative to a point of the cell (float is enough: a cell
/// is small). Point l has id idBase + idOffset[l].
struct SteinerCellView {
  const VertexId* corners;
  int cornerCount;
  int pointCount;
  SteinerPointId idBase;
  const SteinerPointId* idOffset;
  const Vec3f* position;
  Vec3f self;
};

/// Cubes between voxel centres; see steinerPointPosition for the numbering.
/// Only voxels of the domain carry points (every cell corner is one), so a
/// brain in a large image pays for its mask, not for the background.
class GridSteinerCells {
 public:
  /// Without `findCells` only the numbering and positions are set up (no
  /// propagation possible).
  GridSteinerCells(const VoxelGridDomain& domain, int steinerPoints, bool findCells = true);

  std::uint64_t pointCount() const { return pointCount_; }
  /// The centre point of voxel v; kNoVertex when v is outside the domain.
  SteinerPointId pointOfVertex(VertexId v) const {
    const std::uint32_t n = numberOf(v);
    return n == kNoVertex ? kNoVertex : n * slots_;
  }
  /// The voxel of point p, when p is a voxel centre; kNoVertex otherwise.
  VertexId vertexOfPoint(SteinerPointId p) const {
    const std::uint32_t n = slotDivisor_.divide(p);
    return p == n * slots_ ? voxelOf(n) : kNoVertex;
  }
  Vec3d position(SteinerPointId p) const;
  /// Points on the boundary of the largest cell.
  int maxCellPoints() const { return static_cast<int>(position_.size()); }
  int maxCellCorners() const { return 8; }

  template <class F>
  void forEachCellAround(SteinerPointId u, F&& f) {
    const std::uint32_t n = slotDivisor_.divide(u);
    const std::uint32_t slot = u - n * slots_;
    const VoxelIndex c = domain_.indexOf(voxelOf(n));
    const int points = static_cast<int>(position_.size());
    for (const Incidence& in : around_[slot]) {
      if (c.i < in.d[0] || c.j < in.d[1] || c.k < in.d[2]) continue;
      const VertexId base = domain_.vertexAt(c.i - in.d[0], c.j - in.d[1], c.k - in.d[2]);
      if (!isCell_[base]) continue;
      // The cube's points are numbered with its eight corner voxels.
      std::uint32_t first[8];
      for (int corner = 0; corner < 8; ++corner) {
        corners_[corner] = base + cornerOffset_[corner];
        first[corner] = numberOf(corners_[corner]) * slots_;
      }
      for (int l = 0; l < points; ++l) id_[l] = first[pointCorner_[l]] + pointSlot_[l];
      f(SteinerCellView{corners_.data(), 8, points, 0, id_.data(), position_.data(), position_[in.local]});
    }
  }

 private:
  struct Incidence {
    std::array<int, 3> d;  // index offset from the cube's base corner to the point's voxel
    int local;             // the point's index among the cube's boundary points
  };
  /// Number of voxel v among the domain's voxels (index order), kNoVertex outside.
  std::uint32_t numberOf(VertexId v) const { return numberOfVoxel_.empty() ? v : numberOfVoxel_[v]; }
  VertexId voxelOf(std::uint32_t n) const { return voxelOfNumber_.empty() ? n : voxelOfNumber_[n]; }

  const VoxelGridDomain& domain_;
  int m_;
  std::uint32_t slots_;
  std::uint64_t pointCount_;
  detail::FixedDivisor slotDivisor_;
  std::vector<Vec3f> position_;            // per boundary point of a cube, from its base corner
  std::vector<std::uint8_t> pointCorner_;  // per boundary point of a cube: the corner voxel numbering it
  std::vector<std::uint32_t> pointSlot_;   // per boundary point of a cube: its slot at that voxel
  std::vector<SteinerPointId> id_;         // per boundary point: its id in the cube at hand
  // Empty when every voxel is in the domain (the numbering is the identity).
  std::vector<std::uint32_t> numberOfVoxel_;
  std::vector<VertexId> voxelOfNumber_;
  std::vector<Vec3d> slotIndexOffset_;    // per slot: continuous index offset from its voxel
  std::vector<std::vector<Incidence>> around_;  // per slot: the cubes around such a point
  std::array<VertexId, 8> cornerOffset_{};
  std::array<VertexId, 8> corners_{};
  std::vector<std::uint8_t> isCell_;  // per voxel: is the cube with this base corner a cell
};

/// Tetrahedra; see steinerPointPosition for the numbering.
class TetSteinerCells {
 public:
  TetSteinerCells(const TetrahedralCells& cells, int steinerPoints);

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

/// Faces of a polygon surface, each one cell (polygons are not
/// triangulated); see steinerPointPosition for the numbering. Built once from
/// the surface's faces: the undirected edges, each face's edge per side, the
/// faces on each edge (one or two) and the faces around each vertex.
class SurfaceSteinerCells {
 public:
  SurfaceSteinerCells(const SurfaceDomain& surface, int steinerPoints);

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
