// Trilinear sampling on a voxel grid, and the test whether a segment keeps
// to the domain's region, shared by the path tracer and the path refinement
// (internal to the library).
#pragma once

#include <algorithm>
#include <cmath>
#include <vector>

#include "stvd/metric/metric_field.hpp"
#include "stvd/types.hpp"
#include "stvd/voxel_grid/voxel_grid_domain.hpp"

namespace stvd::detail {

/// Where a continuous index falls in the grid: the cell (lower corner
/// `base`) and the trilinear weights of its eight corners.
struct CellSample {
  VertexId corner[8];
  double weight[8];
  double frac[3];
};

/// Locates the continuous index c. False when c lies outside the box of
/// voxel centres by more than a rounding margin: 1e-3 index units, because
/// GridGeometry::physicalPointToIndex inverts the direction matrix by its
/// transpose, and direction cosines read from single-precision headers are
/// orthonormal only to about 1e-7 (an error of about 1e-5 at index 100).
/// A singleton axis accepts |c| <= 0.5 and has weight only on its one layer.
inline bool locate(const VoxelGridDomain& domain, Vec3d c, CellSample& s) {
  constexpr double kMargin = 1e-3;
  const auto& size = domain.geometry().size;
  const double ci[3] = {c.x, c.y, c.z};
  int lo[3], hi[3];
  double frac[3];
  for (int a = 0; a < 3; ++a) {
    const double last = static_cast<double>(size[a]) - 1.0;
    if (size[a] == 1) {
      if (!(std::abs(ci[a]) <= 0.5)) return false;
      lo[a] = hi[a] = 0;
      frac[a] = 0.0;
      continue;
    }
    if (!(ci[a] >= -kMargin && ci[a] <= last + kMargin)) return false;
    const double clamped = std::clamp(ci[a], 0.0, last);
    lo[a] = std::min(static_cast<int>(std::floor(clamped)), static_cast<int>(size[a]) - 2);
    hi[a] = lo[a] + 1;
    frac[a] = clamped - lo[a];
  }
  for (int a = 0; a < 3; ++a) s.frac[a] = frac[a];
  for (int n = 0; n < 8; ++n) {
    const int i = (n & 1) ? hi[0] : lo[0], j = (n & 2) ? hi[1] : lo[1], k = (n & 4) ? hi[2] : lo[2];
    s.corner[n] = domain.vertexAtUnchecked(i, j, k);
    s.weight[n] = ((n & 1) ? frac[0] : 1.0 - frac[0]) * ((n & 2) ? frac[1] : 1.0 - frac[1]) *
                  ((n & 4) ? frac[2] : 1.0 - frac[2]);
  }
  return true;
}

/// The voxels a path may use: in the domain and reached by the propagation.
struct ReachedVoxel {
  const VoxelGridDomain& domain;
  const std::vector<double>& distance;
  bool operator()(VertexId v) const { return domain.contains(v) && std::isfinite(distance[v]); }
};

/// How close (index units) a point must be to a lattice plane to count as
/// on it. The conversion from physical points to indices inverts the
/// direction matrix by its transpose, and direction cosines read from
/// single-precision headers are orthonormal only to about 1e-7: a voxel
/// centre of the shipped brain comes back up to 1e-7 off its integer
/// index, and other files may be off by 1e-5 at index 100. A path must not
/// be refused, nor a jump misdirected, for that; a point may in exchange lie
/// this far inside a cell with an excluded corner.
inline constexpr double kOnPlane = 1e-4;
/// The same for the points a path tracer or refinement places anew: they
/// must lie this close to the region, so that after another conversion to
/// physical space and back they still lie within kOnPlane of it.
inline constexpr double kNewPointOnPlane = 1e-6;

/// The corners of the smallest lattice face (vertex, edge, square or cube)
/// that holds a located point, as a bit mask over cell.corner, and in
/// `moving` a bit per axis along which that face extends; fractions within
/// `onPlane` of 0 or 1 count as 0 or 1.
inline int faceCorners(const CellSample& cell, int& moving, double onPlane = kOnPlane) {
  int fixedHigh = 0;
  moving = 0;
  for (int axis = 0; axis < 3; ++axis) {
    if (cell.frac[axis] >= 1.0 - onPlane)
      fixedHigh |= 1 << axis;
    else if (cell.frac[axis] > onPlane)
      moving |= 1 << axis;
  }
  int corners = 0;
  for (int n = 0; n < 8; ++n)
    if ((n & ~moving) == fixedHigh) corners |= 1 << n;
  return corners;
}

/// Whether the domain's connectivity joins voxels diagonal across a face
/// that extends along `moving` (a bit per axis): 2 axes with Edges or
/// Corners, 3 with Corners.
inline bool joinsDiagonalsAcross(VoxelConnectivity connectivity, int moving) {
  const int axes = (moving & 1) + ((moving >> 1) & 1) + ((moving >> 2) & 1);
  return (axes == 2 && connectivity != VoxelConnectivity::Faces) ||
         (axes == 3 && connectivity == VoxelConnectivity::Corners);
}

/// Whether a located point whose smallest face (faceCorners) has corners
/// outside `usable` lies on a contact that the domain's connectivity joins:
/// the diagonal of that face between two usable opposite corners. Then
/// `from` and `to` are those corners (indices into cell.corner) and t the
/// point's place between them, 0 at `from`.
template <class Usable>
bool onJoinedContact(const VoxelGridDomain& domain, const CellSample& cell, int corners, int moving,
                     const Usable& usable, int& from, int& to, double& t) {
  if (!joinsDiagonalsAcross(domain.connectivity(), moving)) return false;
  for (int corner = 0; corner < 8; ++corner) {
    const int opposite = corner ^ moving;
    if (!((corners >> corner) & 1) || opposite < corner || !usable(cell.corner[corner]) ||
        !usable(cell.corner[opposite]))
      continue;
    // Along the diagonal every moving coordinate is the same distance from
    // `corner`'s side.
    double first = -1.0;
    bool on = true;
    for (int axis = 0; axis < 3 && on; ++axis) {
      if (!((moving >> axis) & 1)) continue;
      const double along = ((corner >> axis) & 1) ? 1.0 - cell.frac[axis] : cell.frac[axis];
      if (first < 0.0) first = along;
      on = std::abs(along - first) < kOnPlane;
    }
    if (on) {
      from = corner;
      to = opposite;
      t = first;
      return true;
    }
  }
  return false;
}

/// Whether the continuous index c lies in the region of the voxels for which
/// `usable(v)` holds (in the domain and, for paths, reached): every corner
/// of the smallest face that holds it (faceCorners) is usable.
template <class Usable>
bool pointInRegion(const VoxelGridDomain& domain, Vec3d c, const Usable& usable, double onPlane = kOnPlane) {
  CellSample cell;
  if (!locate(domain, c, cell)) return false;
  int moving;
  const int corners = faceCorners(cell, moving, onPlane);
  for (int n = 0; n < 8; ++n)
    if (((corners >> n) & 1) && !usable(cell.corner[n])) return false;
  return true;
}

/// Whether every point of the segment a -> b (continuous indices) lies in
/// the region of the usable voxels (pointInRegion), or on a contact that the
/// domain's connectivity joins: the diagonal between two usable voxels that
/// touch only along an edge (VoxelConnectivity::Edges, Corners) or at a
/// corner (Corners) of their voxels, as VoxelGridDomain::segmentInDomain
/// decides for the segments between voxel centres. The segment is cut where
/// it crosses integer planes; between two cuts it runs inside one cell or
/// face, so testing the middle of each piece is exact (up to kOnPlane). A
/// piece on a contact lies on the diagonal between two opposite corners of
/// its face, to within kOnPlane.
/// Segments crossing more than kMaxSegmentCrossings planes along an axis
/// (paths are tested in pieces well under a voxel) are refused.
inline constexpr int kMaxSegmentCrossings = 24;

template <class Usable>
bool segmentInRegion(const VoxelGridDomain& domain, Vec3d a, Vec3d b, const Usable& usable) {
  // Most segments of a path lie in one cell whose corners are all usable.
  {
    CellSample cell;
    if (!locate(domain, a, cell)) return false;
    const VoxelIndex low = domain.indexOf(cell.corner[0]), high = domain.indexOf(cell.corner[7]);
    if (b.x >= low.i && b.x <= high.i && b.y >= low.j && b.y <= high.j && b.z >= low.k && b.z <= high.k) {
      bool all = true;
      for (int n = 0; n < 8 && all; ++n) all = usable(cell.corner[n]);
      if (all) return true;
    }
  }
  const double from[3] = {a.x, a.y, a.z}, to[3] = {b.x, b.y, b.z};
  double cuts[2 + 3 * kMaxSegmentCrossings];
  int count = 0;
  cuts[count++] = 0.0;
  for (int axis = 0; axis < 3; ++axis) {
    const double lo = std::min(from[axis], to[axis]), hi = std::max(from[axis], to[axis]);
    if (hi - lo > kMaxSegmentCrossings) return false;
    for (double plane = std::floor(lo) + 1.0; plane < hi; plane += 1.0)
      cuts[count++] = (plane - from[axis]) / (to[axis] - from[axis]);
  }
  cuts[count++] = 1.0;
  std::sort(cuts, cuts + count);
  for (int n = 1; n < count; ++n) {
    if (!(cuts[n] > cuts[n - 1])) continue;
    const Vec3d p = a + cuts[n - 1] * (b - a), q = a + cuts[n] * (b - a);
    CellSample cell;
    if (!locate(domain, 0.5 * (p + q), cell)) return false;
    int moving;
    const int corners = faceCorners(cell, moving);
    bool inside = true;
    for (int corner = 0; corner < 8 && inside; ++corner)
      if ((corners >> corner) & 1) inside = usable(cell.corner[corner]);
    if (inside) continue;
    // The piece lies in the open square or cube spanned by the moving axes:
    // in the region only along a joined contact, one of its diagonals.
    int from, to;
    double t;
    if (!onJoinedContact(domain, cell, corners, moving, usable, from, to, t)) return false;
    const VoxelIndex e0 = domain.indexOf(cell.corner[from]), e1 = domain.indexOf(cell.corner[to]);
    const Vec3d c0{double(e0.i), double(e0.j), double(e0.k)};
    const Vec3d d = Vec3d{double(e1.i), double(e1.j), double(e1.k)} - c0;
    auto offLine = [&](Vec3d x) { return norm((x - c0) - (dot(x - c0, d) / dot(d, d)) * d); };
    if (!(offLine(p) < kOnPlane && offLine(q) < kOnPlane)) return false;
  }
  return true;
}

/// A 3x3 symmetric matrix in double precision.
struct Sym3 {
  double xx = 0, xy = 0, xz = 0, yy = 0, yz = 0, zz = 0;
  void add(double w, const SymTensor3& t) {
    xx += w * t.xx;
    xy += w * t.xy;
    xz += w * t.xz;
    yy += w * t.yy;
    yz += w * t.yz;
    zz += w * t.zz;
  }
  double quadraticForm(Vec3d v) const {
    return xx * v.x * v.x + yy * v.y * v.y + zz * v.z * v.z +
           2.0 * (xy * v.x * v.y + xz * v.x * v.z + yz * v.y * v.z);
  }
  /// G^-1 v through the adjugate; false when G is singular.
  bool solve(Vec3d v, Vec3d& out) const {
    const double a00 = yy * zz - yz * yz, a01 = xz * yz - xy * zz, a02 = xy * yz - xz * yy;
    const double a11 = xx * zz - xz * xz, a12 = xy * xz - xx * yz, a22 = xx * yy - xy * xy;
    const double det = xx * a00 + xy * a01 + xz * a02;
    if (!(det > 0.0) || !std::isfinite(det)) return false;
    out = {(a00 * v.x + a01 * v.y + a02 * v.z) / det, (a01 * v.x + a11 * v.y + a12 * v.z) / det,
           (a02 * v.x + a12 * v.y + a22 * v.z) / det};
    return true;
  }
};

}  // namespace stvd::detail
