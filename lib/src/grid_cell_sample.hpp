// Trilinear sampling on a voxel grid, shared by the path tracer and the
// path refinement (internal to the library).
#pragma once

#include <algorithm>
#include <cmath>

#include "stvd/metric_field.hpp"
#include "stvd/types.hpp"
#include "stvd/voxel_grid_domain.hpp"

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
    s.corner[n] = domain.vertexAt(i, j, k);
    s.weight[n] = ((n & 1) ? frac[0] : 1.0 - frac[0]) * ((n & 2) ? frac[1] : 1.0 - frac[1]) *
                  ((n & 4) ? frac[2] : 1.0 - frac[2]);
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
