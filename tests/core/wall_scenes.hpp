// Thin walls in a slab of 1 mm voxels under the Euclidean metric, with
// distances worked out by hand: the scenes on which every method, and the
// paths, must keep to the domain's region (VoxelConnectivity).
//
// The domain's region is the union of the closed cells (segments, squares,
// cubes between voxel centres) whose corners are all domain voxels: a wall
// voxel at index x0 removes the open cells around it, so in the plane it is
// an open square (x0 - 1, x0 + 1) x (y0 - 1, y0 + 1) that paths go around.
#pragma once

#include <array>
#include <cmath>
#include <cstdint>
#include <vector>

#include "stvd/metric/metric_field.hpp"
#include "stvd/propagation/propagation.hpp"
#include "stvd/voxel_grid/voxel_grid_domain.hpp"
#include "stvd/voxel_grid/voxel_grid_propagation.hpp"

namespace stvd::test {

/// A slab of nx x ny x nz voxels of 1 mm with a mask.
struct Slab {
  GridGeometry geometry;
  std::vector<std::uint8_t> mask;

  Slab(int nx, int ny, int nz) {
    geometry.size = {std::size_t(nx), std::size_t(ny), std::size_t(nz)};
    mask.assign(geometry.voxelCount(), 1);
  }
  std::size_t at(int i, int j, int k) const {
    return i + geometry.size[0] * (j + geometry.size[1] * std::size_t(k));
  }
  void exclude(int i, int j, int k) { mask[at(i, j, k)] = 0; }
  VoxelGridDomain domain(const Stencil& stencil, VoxelConnectivity connectivity = VoxelConnectivity::Faces) const {
    return VoxelGridDomain(geometry, stencil, mask, connectivity);
  }
  RiemannianMetric identityMetric() const {
    return RiemannianMetric::constant(geometry.voxelCount(), SymTensor3{1.f, 0.f, 0.f, 1.f, 0.f, 1.f});
  }
};

inline double length(double dx, double dy, double dz = 0.0) { return std::sqrt(dx * dx + dy * dy + dz * dz); }

/// A masked slab, a source and a target voxel, and the length of the
/// shortest path between them inside the region for each connectivity
/// (kUnreachable where there is none).
struct WallScene {
  const char* name;
  Slab slab;
  std::array<int, 3> source, target;
  double faces, edges, corners;  // the exact distance per VoxelConnectivity

  double exact(VoxelConnectivity c) const {
    return c == VoxelConnectivity::Faces ? faces : c == VoxelConnectivity::Edges ? edges : corners;
  }
};

/// Wall x = 20, y = 0..34, through the whole 40 x 40 x 3 slab; the gap is
/// y = 35..39. The removed region is 19 < x < 21, y < 35, so the shortest
/// path from (10, 5) to (30, 5) runs over the corners (19, 35) and (21, 35):
/// 64.64 mm. With VoxelConnectivity::Edges (or Corners) the diagonal steps
/// (19, 34) -> (20, 35) -> (21, 34) past the wall's end voxel are joined
/// too (the voxels share an edge), which cuts the corners: 63.56 mm.
inline WallScene straightWallWithGap() {
  WallScene s{"straight wall", Slab(40, 40, 3), {10, 5, 1}, {30, 5, 1}, 0, 0, 0};
  for (int k = 0; k < 3; ++k)
    for (int j = 0; j <= 34; ++j) s.slab.exclude(20, j, k);
  s.faces = 2.0 * length(9, 30) + 2.0;
  s.edges = s.corners = 2.0 * length(9, 29) + 2.0 * std::sqrt(2.0);
  return s;
}

/// Wall voxels (i, i), i = 0..34, through the 40 x 40 x 3 slab: neighbours
/// along it touch only along an edge. The removed region is the union of
/// the open squares (i - 1, i + 1)^2, from the image's corner to (35, 35):
/// with VoxelConnectivity::Faces the way from (30, 10) to (10, 30) runs
/// around the end over (35, 33), (35, 35) and (33, 35): 51.07 mm. With
/// Edges (or Corners) the voxels (i + 1, i) and (i, i + 1) are joined by
/// the step between them, so the wall can be crossed anywhere; the shortest
/// crossing is (20, 19) -> (19, 20): 28.32 mm.
inline WallScene diagonalWall() {
  WallScene s{"diagonal wall", Slab(40, 40, 3), {30, 10, 1}, {10, 30, 1}, 0, 0, 0};
  for (int k = 0; k < 3; ++k)
    for (int i = 0; i <= 34; ++i) s.slab.exclude(i, i, k);
  s.faces = 2.0 * length(5, 23) + 4.0;
  s.edges = s.corners = 2.0 * length(10, 9) + std::sqrt(2.0);
  return s;
}

/// A wall ten voxels thick (x = 15..24) through the 40 x 40 x 3 slab with
/// one open line of voxels, y = 20, z = 1, through it. Inside the wall only
/// the segment between those voxel centres lies in the region:
/// (5, 10) -> (14, 20) -> (25, 20) -> (34, 30), 37.91 mm. With
/// VoxelConnectivity::Edges (or Corners) the tunnel's end voxels are also
/// joined to their diagonal neighbours outside the wall:
/// (5, 10) -> (14, 19) -> (15, 20) -> (24, 20) -> (25, 21) -> (34, 30),
/// 37.28 mm.
inline WallScene oneVoxelTunnel() {
  WallScene s{"one-voxel tunnel", Slab(40, 40, 3), {5, 10, 1}, {34, 30, 1}, 0, 0, 0};
  for (int k = 0; k < 3; ++k)
    for (int j = 0; j < 40; ++j)
      for (int i = 15; i <= 24; ++i)
        if (!(j == 20 && k == 1)) s.slab.exclude(i, j, k);
  s.faces = 2.0 * length(9, 10) + 11.0;
  s.edges = s.corners = 20.0 * std::sqrt(2.0) + 9.0;
  return s;
}

/// Two boxes of voxels in a 22 x 22 x 4 slab that share one corner of their
/// cubes: x, y <= 10, z <= 1 and x, y >= 11, z >= 2. Only the step
/// (10, 10, 1) -> (11, 11, 2) joins them, and only with
/// VoxelConnectivity::Corners: (2, 4, 0) -> (10, 10, 1) -> (11, 11, 2) ->
/// (17, 19, 3).
inline WallScene blocksTouchingAtACorner() {
  WallScene s{"corner contact", Slab(22, 22, 4), {2, 4, 0}, {17, 19, 3}, 0, 0, 0};
  for (int k = 0; k < 4; ++k)
    for (int j = 0; j < 22; ++j)
      for (int i = 0; i < 22; ++i) {
        const bool low = i <= 10 && j <= 10 && k <= 1, high = i >= 11 && j >= 11 && k >= 2;
        if (!low && !high) s.slab.exclude(i, j, k);
      }
  s.faces = s.edges = kUnreachable;
  s.corners = length(8, 6, 1) + std::sqrt(3.0) + length(6, 8, 1);
  return s;
}

inline std::vector<WallScene> wallScenes() {
  return {straightWallWithGap(), diagonalWall(), oneVoxelTunnel(), blocksTouchingAtACorner()};
}

inline const VoxelConnectivity kConnectivities[] = {VoxelConnectivity::Faces, VoxelConnectivity::Edges,
                                                    VoxelConnectivity::Corners};

}  // namespace stvd::test
