// A constant metric given along the index axes of an oblique grid with
// unequal spacings: its exact geodesic distances are known in closed form,
// so files that encode it in any layout, order or frame can be checked
// against numbers that no reader produced.
#pragma once

#include <array>
#include <cmath>
#include <vector>

#include "stvd/imaging/tensor_frames.hpp"
#include "stvd/voxel_grid/stencil.hpp"
#include "test_support.hpp"

namespace stvd::testing {

struct KnownField {
  HandGeometry geometry;
  /// The metric's components along the index axes (unit vectors).
  SymTensor3 voxelFrameMetric{2.0f, 0.3f, -0.2f, 1.0f, 0.1f, 0.5f};
  /// A measurement frame for the NRRD files, unrelated to the grid axes.
  Matrix3 measurementFrameLps = rotation(-2, 1, 1, 50);

  KnownField() {
    geometry.size = {11, 9, 7};
    geometry.spacing = {1.0, 1.5, 2.0};
    geometry.originLps = {-12.5, 30.25, -7.0};
    geometry.directionLps = rotation(1, 2, 3, 30);  // oblique, determinant +1
  }
  std::size_t voxelCount() const { return std::size_t(geometry.size[0]) * geometry.size[1] * geometry.size[2]; }
  std::array<int, 3> centre() const { return {5, 4, 3}; }

  /// The metric in LPS: R G R^T.
  SymTensor3 lpsMetric() const { return imaging::changeTensorFrame(voxelFrameMetric, geometry.directionLps); }
  /// The metric in RAS: F R G R^T F.
  SymTensor3 rasMetric() const { return imaging::changeTensorFrame(lpsMetric(), imaging::rasToLps()); }
  /// The components a NRRD file stores in its measurement frame: M^T G_LPS M.
  SymTensor3 measurementFrameMetric() const { return conjugateTranspose(lpsMetric(), measurementFrameLps); }

  /// sqrt(u^T G u) with u = diag(spacing) (b - a): the exact distance.
  double exactDistance(const std::array<int, 3>& a, const std::array<int, 3>& b) const {
    const double u[3] = {geometry.spacing[0] * (b[0] - a[0]), geometry.spacing[1] * (b[1] - a[1]),
                         geometry.spacing[2] * (b[2] - a[2])};
    const SymTensor3& g = voxelFrameMetric;
    const double q = g.xx * u[0] * u[0] + g.yy * u[1] * u[1] + g.zz * u[2] * u[2] +
                     2.0 * (g.xy * u[0] * u[1] + g.xz * u[0] * u[2] + g.yz * u[1] * u[2]);
    return std::sqrt(q);
  }

  /// Every voxel on a straight stencil line through the centre (all 26
  /// directions, as far as the grid goes), where even Dijkstra is exact for
  /// a constant metric. Voxel indices (i, j, k).
  std::vector<std::array<int, 3>> voxelsOnStencilLines() const {
    std::vector<std::array<int, 3>> voxels;
    const auto c = centre();
    const Stencil stencil = Stencil::full26();
    for (const auto& o : stencil.offsets())
      for (int n = 1;; ++n) {
        const std::array<int, 3> p{c[0] + n * o[0], c[1] + n * o[1], c[2] + n * o[2]};
        bool inside = true;
        for (int a = 0; a < 3; ++a) inside = inside && p[a] >= 0 && p[a] < geometry.size[a];
        if (!inside) break;
        voxels.push_back(p);
      }
    return voxels;
  }
  std::size_t linear(const std::array<int, 3>& p) const {
    return std::size_t(p[0]) + std::size_t(geometry.size[0]) * (std::size_t(p[1]) + std::size_t(geometry.size[1]) * p[2]);
  }
};

}  // namespace stvd::testing
