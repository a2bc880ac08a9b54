// The Steiner-point layout over a voxel grid's region (private to the
// library): it numbers the points of Lanthier's graph and, for a point u,
// hands every cell around u to Lanthier's Dijkstra as a SteinerCellView
// (lanthier/lanthier_dijkstra.hpp).
#pragma once

#include <array>
#include <cstdint>
#include <vector>

#include "lanthier/lanthier_dijkstra.hpp"
#include "stvd/voxel_grid/voxel_grid_domain.hpp"

namespace stvd::detail {

/// The cells of a voxel grid's domain region (VoxelConnectivity), each
/// joining its points by straight segments measured with the mean norm of its
/// corners:
/// - the complete cubes between voxel centres (all eight corners in the
///   domain);
/// - every grid edge between two domain voxels, as a 1D cell with its M
///   points, measured as Dijkstra measures the edge (the mean of its two
///   ends), so that no distance exceeds Dijkstra's on the 6-neighbourhood:
///   a one-voxel strand, and the edges along which the cubes' mean norms
///   are dearer than the edge's own;
/// - the complete squares (four corners in the domain) that lie in no
///   complete cube, as 2D cells: a one-voxel-thick sheet;
/// - with VoxelConnectivity::Edges or Corners, the diagonals between two
///   domain voxels that touch only along an edge (across a square) or, with
///   Corners, at a corner (across a cube), as 1D cells of their two ends.
/// So the graph covers exactly the region that Dijkstra's steps and STVD's
/// candidates are held to, and every lower-dimensional cell uses the points
/// that the voxel, edge and face slots already number: see
/// steinerPointPosition. Only voxels of the domain carry points (every cell
/// corner is one), so a brain in a large image pays for its mask, not for
/// the background.
class GridSteinerCells {
 public:
  /// The numbering and positions only (no propagation possible).
  GridSteinerCells(const VoxelGridDomain& domain, int steinerPoints);
  /// The numbering and the cells, reporting setupSteps(domain) steps to
  /// `setup` (one per voxel of each pass over the grid).
  GridSteinerCells(const VoxelGridDomain& domain, int steinerPoints, SetupProgress& setup);
  static std::uint64_t setupSteps(const VoxelGridDomain& domain);

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
  /// Points on the boundary of the largest cell (a cube).
  int maxCellPoints() const { return static_cast<int>(shapes_[kCube].position.size()); }
  int maxCellCorners() const { return 8; }

  template <class F>
  void forEachCellAround(SteinerPointId u, F&& f) {
    const std::uint32_t n = slotDivisor_.divide(u);
    const std::uint32_t slot = u - n * slots_;
    const VoxelIndex c = domain_.indexOf(voxelOf(n));
    // The cubes and edges come first; squares and diagonals exist only where
    // the domain is thin, and never without a mask on a grid of at least two
    // voxels along every axis. One call site of f keeps it inlined.
    const std::vector<Incidence>& around = around_[slot];
    const std::size_t count = hasThinCells_ ? around.size() : cubesAndEdgesAround_[slot];
    for (std::size_t a = 0; a < count; ++a) {
      const Incidence& in = around[a];
      if (c.i < in.d[0] || c.j < in.d[1] || c.k < in.d[2]) continue;
      const VertexId base = domain_.vertexAtUnchecked(c.i - in.d[0], c.j - in.d[1], c.k - in.d[2]);
      if (!(flags_[base] & in.flag)) continue;
      const Shape& shape = shapes_[in.shape];
      // The cell's points are numbered with its corner voxels. A shape with
      // fewer than eight corners repeats its base voxel in the unused ones
      // (a voxel of the image, never read by a point): a loop of constant
      // length is unrolled for the cubes.
      std::uint32_t first[8];
      for (int corner = 0; corner < 8; ++corner) {
        corners_[corner] = base + shape.cornerOffset[corner];
        first[corner] = numberOf(corners_[corner]) * slots_;
      }
      const int points = static_cast<int>(shape.position.size());
      for (int l = 0; l < points; ++l) id_[l] = first[shape.pointCorner[l]] + shape.pointSlot[l];
      f(SteinerCellView{corners_.data(), shape.cornerCount, points, 0, id_.data(), shape.position.data(),
                        shape.position[in.local]});
    }
  }

 private:
  /// The kinds of cell, one per bit of flags_: the cube, the square normal
  /// to axis a, the edge along axis a, the two diagonals of the square
  /// normal to a, and the four diagonals of the cube (corner n to corner
  /// 7 - n, corner bits i, j, k).
  enum ShapeIndex : int { kCube = 0, kSquare = 1, kEdge = 4, kFaceDiagonal = 7, kBodyDiagonal = 13, kShapes = 17 };
  /// One kind of cell, placed at its base voxel (the lowest corner of its
  /// cube or square, which need not be in the domain for a diagonal).
  struct Shape {
    int cornerCount = 0;
    std::array<std::array<int, 3>, 8> cornerIndex{};  // index offsets of the corners from the base voxel
    std::array<VertexId, 8> cornerOffset{};           // the same as linear offsets (0 past cornerCount)
    std::vector<Vec3f> position;                      // per point, from the base voxel's centre
    std::vector<std::uint8_t> pointCorner;            // per point: the corner voxel numbering it
    std::vector<std::uint32_t> pointSlot;             // per point: its slot at that voxel
  };
  /// A cell of kind `shape` holds the point of some slot at its voxel, whose
  /// index offset from the cell's base voxel is d, as its point `local`.
  struct Incidence {
    std::array<int, 3> d;
    std::uint32_t flag;  // 1 << shape
    int shape;
    int local;
  };

  /// Number of voxel v among the domain's voxels (index order), kNoVertex outside.
  std::uint32_t numberOf(VertexId v) const { return numberOfVoxel_.empty() ? v : numberOfVoxel_[v]; }
  VertexId voxelOf(std::uint32_t n) const { return voxelOfNumber_.empty() ? n : voxelOfNumber_[n]; }

  GridSteinerCells(const VoxelGridDomain& domain, int steinerPoints, SetupProgress* setup);
  void buildShapes();
  void findCells(SetupProgress& setup);
  /// Without a mask: every square lies in a complete cube, unless an axis
  /// has a single voxel.
  static bool thinCellsPossible(const VoxelGridDomain& domain);

  const VoxelGridDomain& domain_;
  int m_;
  std::uint32_t slots_;
  std::uint64_t pointCount_;
  detail::FixedDivisor slotDivisor_;
  std::array<Shape, kShapes> shapes_;
  std::vector<SteinerPointId> id_;  // per point of a cell: its id in the cell at hand
  // Empty when every voxel is in the domain (the numbering is the identity).
  std::vector<std::uint32_t> numberOfVoxel_;
  std::vector<VertexId> voxelOfNumber_;
  std::vector<Vec3d> slotIndexOffset_;          // per slot: continuous index offset from its voxel
  std::vector<std::vector<Incidence>> around_;  // per slot: the cells around such a point, cubes and edges first
  std::vector<std::size_t> cubesAndEdgesAround_;  // per slot: how many of them are cubes or edges
  std::array<VertexId, 8> corners_{};
  std::vector<std::uint32_t> flags_;  // per base voxel: bit s set when the cell of shape s there is one
  bool hasThinCells_ = false;  // some square or diagonal is a cell
};

}  // namespace stvd::detail
