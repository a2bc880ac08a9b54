// Vertex values resampled onto a voxel grid: barycentric interpolation
// reproduces linear functions exactly, the RAS/LPS relation is honoured, and
// voxels outside the mesh or in unreachable tetrahedra get the outside value.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>

#include "../core/kuhn_lattice.hpp"
#include "stvd/tetmesh/grid_resampling.hpp"

namespace stvd::tetmesh {
namespace {

/// The box [0,2] x [0,1] x [0,1] (mesh coordinates, shifted by `origin`) as
/// two unit cubes, each cut into six tetrahedra around its diagonal.
TetMesh twoCubes(Vec3d origin) {
  TetMesh m;
  auto id = [](int i, int j, int k) { return static_cast<VertexId>(i + 3 * (j + 2 * k)); };
  for (int k = 0; k <= 1; ++k)
    for (int j = 0; j <= 1; ++j)
      for (int i = 0; i <= 2; ++i) m.points.push_back(origin + Vec3d{double(i), double(j), double(k)});
  for (int i = 0; i < 2; ++i)
    test::forEachKuhnTetrahedron(i, 0, 0, id, [&m](const std::array<VertexId, 4>& t) { m.tets.push_back(t); });
  return m;
}

double linear(Vec3d p) { return 3.0 * p.x - 2.0 * p.y + 0.5 * p.z + 7.0; }

TEST(GridResampling, ReproducesALinearFieldAndMarksVoxelsOutsideTheMesh) {
  const TetMesh mesh = twoCubes({1.0, 2.0, 3.0});
  std::vector<double> values;
  for (const Vec3d& p : mesh.points) values.push_back(linear(p));
  GridGeometry grid;  // an oblique grid partly covering the mesh (LPS = mesh frame)
  grid.size = {12, 7, 6};
  grid.spacing = {0.25, 0.2, 0.3};
  grid.origin = {0.8, 1.9, 2.9};
  const double c = std::cos(0.2), s = std::sin(0.2);
  grid.direction = {c, 0, s, 0, 1, 0, -s, 0, c};
  const std::vector<double> out = resampleOntoGrid(mesh, values, grid, MeshFrame::Lps, -1.0);
  std::size_t inside = 0, outside = 0;
  for (std::size_t k = 0; k < grid.size[2]; ++k)
    for (std::size_t j = 0; j < grid.size[1]; ++j)
      for (std::size_t i = 0; i < grid.size[0]; ++i) {
        const Vec3d x = grid.indexToPhysicalPoint(double(i), double(j), double(k));
        const double v = out[i + grid.size[0] * (j + grid.size[1] * k)];
        const bool in = x.x >= 1.0 - 1e-12 && x.x <= 3.0 + 1e-12 && x.y >= 2.0 - 1e-12 && x.y <= 3.0 + 1e-12 &&
                        x.z >= 3.0 - 1e-12 && x.z <= 4.0 + 1e-12;
        if (in) {
          ++inside;
          EXPECT_NEAR(v, linear(x), 1e-9) << i << " " << j << " " << k;
        } else {
          ++outside;
          EXPECT_EQ(v, -1.0) << i << " " << j << " " << k;
        }
      }
  EXPECT_GT(inside, 50u);
  EXPECT_GT(outside, 50u);
}

TEST(GridResampling, ARasMeshIsFlippedIntoTheGridsLpsFrame) {
  const TetMesh mesh = twoCubes({1.0, 2.0, 3.0});  // RAS
  std::vector<double> values;
  for (const Vec3d& p : mesh.points) values.push_back(linear(p));
  GridGeometry grid;  // LPS voxel centres (-1.5, -2.5, 3.5) and (1.5, 2.5, 3.5)
  grid.size = {2, 1, 1};
  grid.spacing = {3.0, 5.0, 1.0};
  grid.origin = {-1.5, -2.5, 3.5};
  const std::vector<double> out = resampleOntoGrid(mesh, values, grid, MeshFrame::Ras, -1.0);
  EXPECT_NEAR(out[0], linear({1.5, 2.5, 3.5}), 1e-9);
  EXPECT_EQ(out[1], -1.0);
}

TEST(GridResampling, VoxelsInTetrahedraWithAnUnreachableCornerGetTheOutsideValue) {
  const TetMesh mesh = twoCubes({0.0, 0.0, 0.0});
  std::vector<double> values(mesh.points.size(), 1.0);
  values[2] = std::numeric_limits<double>::infinity();  // the corner (2, 0, 0)
  GridGeometry grid;
  grid.size = {2, 1, 1};
  grid.spacing = {1.0, 1.0, 1.0};
  // Strictly inside the tetrahedra (0,0,0) (1,0,0) (1,1,0) (1,1,1) and
  // (1,0,0) (2,0,0) (2,1,0) (2,1,1) (x - i > y > z).
  grid.origin = {0.8, 0.1, 0.05};
  const std::vector<double> out = resampleOntoGrid(mesh, values, grid, MeshFrame::Lps, -1.0);
  EXPECT_DOUBLE_EQ(out[0], 1.0);
  EXPECT_EQ(out[1], -1.0);
}

}  // namespace
}  // namespace stvd::tetmesh
