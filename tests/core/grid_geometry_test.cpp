// Physical placement of voxel grids, vertex numbering, neighbourhoods and
// stencils.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <limits>
#include <numeric>
#include <set>
#include <stdexcept>
#include <vector>

#include "exact_metrics.hpp"
#include "scenes.hpp"
#include "stvd/voxel_grid/stencil.hpp"
#include "stvd/voxel_grid/voxel_grid_domain.hpp"

namespace stvd {
namespace {

void expectNear(Vec3d a, Vec3d b, double tolerance) {
  EXPECT_NEAR(a.x, b.x, tolerance);
  EXPECT_NEAR(a.y, b.y, tolerance);
  EXPECT_NEAR(a.z, b.z, tolerance);
}

TEST(GridGeometry, PhysicalPointIsOriginPlusDirectionTimesSpacingTimesIndex) {
  const test::Mat3 axes = test::rotation({1.0, -2.0, 0.5}, 0.7);
  const GridGeometry g = test::orientedGrid({7, 5, 3}, {0.8, 1.5, 2.25}, {-31.5, 12.25, 107.0}, axes);
  const double index[][3] = {{0, 0, 0}, {6, 4, 2}, {2.5, -1.0, 1.75}, {100.0, 3.0, -40.0}};
  for (const auto& c : index) {
    // x = origin + D diag(s) ijk, with the index axes as the columns of D.
    const Vec3d scaled{g.spacing[0] * c[0], g.spacing[1] * c[1], g.spacing[2] * c[2]};
    const Vec3d expected = Vec3d{g.origin[0], g.origin[1], g.origin[2]} + axes * scaled;
    expectNear(g.indexToPhysicalPoint(c[0], c[1], c[2]), expected, 1e-12);
  }
  // Index axis 0 runs along the first column of the direction matrix.
  const Vec3d step = g.indexToPhysicalPoint(1, 0, 0) - g.indexToPhysicalPoint(0, 0, 0);
  expectNear(step, g.spacing[0] * Vec3d{axes(0, 0), axes(1, 0), axes(2, 0)}, 1e-12);
}

TEST(GridGeometry, PhysicalPointToIndexInvertsIndexToPhysicalPoint) {
  const GridGeometry g = test::obliqueGrid({10, 10, 10});
  test::Random random(7);
  for (int n = 0; n < 200; ++n) {
    const Vec3d index{random.uniform(-5, 15), random.uniform(-5, 15), random.uniform(-5, 15)};
    expectNear(g.physicalPointToIndex(g.indexToPhysicalPoint(index.x, index.y, index.z)), index,
               1e-10);
    const Vec3d point{random.uniform(-100, 100), random.uniform(-100, 100), random.uniform(0, 200)};
    const Vec3d back = g.physicalPointToIndex(point);
    expectNear(g.indexToPhysicalPoint(back.x, back.y, back.z), point, 1e-10);
  }
}

TEST(GridGeometry, ValidateRejectsDegenerateGeometry) {
  const GridGeometry good = test::obliqueGrid({4, 4, 4});
  EXPECT_NO_THROW(good.validate());

  GridGeometry g = good;
  g.size[1] = 0;
  EXPECT_THROW(g.validate(), std::invalid_argument);
  g = good;
  g.spacing[2] = 0.0;
  EXPECT_THROW(g.validate(), std::invalid_argument);
  g = good;
  g.spacing[0] = -1.0;
  EXPECT_THROW(g.validate(), std::invalid_argument);
  g = good;
  g.spacing[1] = std::nan("");
  EXPECT_THROW(g.validate(), std::invalid_argument);
  g = good;
  g.origin[0] = std::numeric_limits<double>::infinity();
  EXPECT_THROW(g.validate(), std::invalid_argument);
  g = good;
  g.direction = {1, 0, 0, 0, 1, 0, 0, 0, 1.01};  // not unit length
  EXPECT_THROW(g.validate(), std::invalid_argument);
  g = good;
  g.direction = {1, 0.1, 0, 0, 1, 0, 0, 0, 1};  // columns not orthogonal
  EXPECT_THROW(g.validate(), std::invalid_argument);
  g = good;
  g.size = {65536, 65536, 2};  // more voxels than 32-bit vertex ids
  EXPECT_THROW(g.validate(), std::invalid_argument);
  // A reflection is orthonormal and allowed (NIfTI and ITK images can be
  // left-handed).
  g = good;
  g.direction = {-1, 0, 0, 0, 1, 0, 0, 0, 1};
  EXPECT_NO_THROW(g.validate());
}

TEST(VoxelGridDomain, VertexNumberingIsLinearIndexAndRoundTrips) {
  const VoxelGridDomain domain(test::obliqueGrid({5, 4, 3}), Stencil::full26());
  EXPECT_EQ(domain.vertexCount(), 60u);
  EXPECT_EQ(domain.domainVertexCount(), 60u);
  for (int k = 0; k < 3; ++k)
    for (int j = 0; j < 4; ++j)
      for (int i = 0; i < 5; ++i) {
        const VertexId v = domain.vertexAt(i, j, k);
        EXPECT_EQ(v, static_cast<VertexId>(i + 5 * (j + 4 * k)));
        const VoxelIndex back = domain.indexOf(v);
        EXPECT_EQ(back.i, i);
        EXPECT_EQ(back.j, j);
        EXPECT_EQ(back.k, k);
        expectNear(domain.physicalPoint(v), domain.geometry().indexToPhysicalPoint(i, j, k), 1e-12);
      }
}

TEST(VoxelGridDomain, IndexOfIsExactOnLargeGrids) {
  // indexOf divides by multiplication; check it against integer division at
  // the ends of every row and slice of a grid with awkward sizes.
  GridGeometry g;
  g.size = {1021, 769, 5};
  const VoxelGridDomain domain(g, Stencil::faces6());
  for (VertexId k = 0; k < 5; ++k)
    for (VertexId j : {0u, 1u, 383u, 767u, 768u})
      for (VertexId i : {0u, 1u, 510u, 1019u, 1020u}) {
        const VertexId v = i + 1021u * (j + 769u * k);
        const VoxelIndex c = domain.indexOf(v);
        EXPECT_EQ(static_cast<VertexId>(c.i), i);
        EXPECT_EQ(static_cast<VertexId>(c.j), j);
        EXPECT_EQ(static_cast<VertexId>(c.k), k);
      }
}

TEST(VoxelGridDomain, NeighboursAreStencilOffsetsInsideImageAndMaskWhoseStepStaysInTheDomain) {
  const GridGeometry geometry = test::obliqueGrid({6, 5, 4});
  std::vector<std::uint8_t> mask(geometry.voxelCount(), 1);
  const VoxelGridDomain full(geometry, Stencil::full26());
  mask[full.vertexAt(2, 2, 2)] = 0;
  const VoxelGridDomain masked(geometry, Stencil::full26(), mask);
  EXPECT_EQ(masked.domainVertexCount(), full.vertexCount() - 1);

  const Stencil stencil = Stencil::full26();
  for (const VoxelGridDomain* domain : {&full, &masked}) {
    for (VertexId v = 0; v < domain->vertexCount(); ++v) {
      if (!domain->contains(v)) continue;  // the propagation never asks
      const VoxelIndex c = domain->indexOf(v);
      std::set<VertexId> expected;
      for (const auto& o : stencil.offsets()) {
        const int i = c.i + o[0], j = c.j + o[1], k = c.k + o[2];
        if (!domain->isInsideImage(i, j, k)) continue;
        const VertexId w = domain->vertexAt(i, j, k);
        if (!domain->contains(w)) continue;
        // A diagonal step passes through the square (two non-zero
        // components) or cube (three) that it crosses: every voxel of it
        // must be in the domain (the default connectivity, 6).
        bool stepInDomain = true;
        for (int a = 0; a <= 1; ++a)
          for (int b = 0; b <= 1; ++b)
            for (int d = 0; d <= 1; ++d) {
              const int ci = c.i + (o[0] != 0 ? a * o[0] : 0), cj = c.j + (o[1] != 0 ? b * o[1] : 0),
                        ck = c.k + (o[2] != 0 ? d * o[2] : 0);
              stepInDomain = stepInDomain && domain->contains(domain->vertexAt(ci, cj, ck));
            }
        if (stepInDomain) expected.insert(w);
      }
      std::set<VertexId> seen;
      domain->forEachNeighbor(v, [&](VertexId w, Vec3f e) {
        EXPECT_TRUE(seen.insert(w).second) << "neighbour reported twice";
        const Vec3d d = domain->physicalPoint(w) - domain->physicalPoint(v);
        EXPECT_NEAR(e.x, d.x, 1e-5);
        EXPECT_NEAR(e.y, d.y, 1e-5);
        EXPECT_NEAR(e.z, d.z, 1e-5);
      });
      EXPECT_EQ(seen, expected) << "vertex " << v;
    }
  }
  // A corner voxel of the full grid has 7 neighbours, an interior one 26.
  int corner = 0, interior = 0;
  full.forEachNeighbor(full.vertexAt(0, 0, 0), [&](VertexId, Vec3f) { ++corner; });
  full.forEachNeighbor(full.vertexAt(2, 2, 2), [&](VertexId, Vec3f) { ++interior; });
  EXPECT_EQ(corner, 7);
  EXPECT_EQ(interior, 26);
}

TEST(VoxelGridDomain, RejectsMaskOfWrongSize) {
  const GridGeometry geometry = test::obliqueGrid({4, 4, 4});
  EXPECT_THROW(VoxelGridDomain(geometry, Stencil::faces6(), std::vector<std::uint8_t>(63, 1)),
               std::invalid_argument);
  GridGeometry bad = geometry;
  bad.spacing[0] = 0.0;
  EXPECT_THROW(VoxelGridDomain(bad, Stencil::faces6()), std::invalid_argument);
}

int gcd3(const Stencil::Offset& o) {
  return std::gcd(std::gcd(std::abs(o[0]), std::abs(o[1])), std::abs(o[2]));
}

void expectValidStencil(const Stencil& s) {
  const std::set<Stencil::Offset> unique(s.offsets().begin(), s.offsets().end());
  EXPECT_EQ(unique.size(), s.offsets().size()) << "repeated offset";
  EXPECT_EQ(unique.count({0, 0, 0}), 0u);
  for (const auto& o : s.offsets()) EXPECT_EQ(unique.count({-o[0], -o[1], -o[2]}), 1u);
}

TEST(Stencil, NamedStencilsHaveTheirSizesAndRadii) {
  struct Expected {
    const char* name;
    int size;
    int radius;
  };
  for (const Expected& e : {Expected{"6", 6, 1}, Expected{"18", 18, 1}, Expected{"26", 26, 1},
                            Expected{"98", 98, 2}, Expected{"290", 290, 3}}) {
    const Stencil s = Stencil::byName(e.name);
    EXPECT_EQ(s.size(), e.size) << e.name;
    EXPECT_EQ(s.radius(), e.radius) << e.name;
    expectValidStencil(s);
  }
  EXPECT_EQ(Stencil::byName("6").offsets(), Stencil::faces6().offsets());
  EXPECT_EQ(Stencil::byName("18").offsets(), Stencil::faces18().offsets());
  EXPECT_EQ(Stencil::byName("26").offsets(), Stencil::full26().offsets());
  EXPECT_EQ(Stencil::byName("26").offsets(), Stencil::primitive(1).offsets());
}

TEST(Stencil, OffsetsAreTheExpectedSets) {
  const Stencil faces6 = Stencil::faces6(), faces18 = Stencil::faces18();
  for (const auto& o : faces6.offsets()) EXPECT_EQ(std::abs(o[0]) + std::abs(o[1]) + std::abs(o[2]), 1);
  for (const auto& o : faces18.offsets()) EXPECT_LE(o[0] * o[0] + o[1] * o[1] + o[2] * o[2], 2);
  // The large stencils hold exactly the primitive offsets of their block.
  for (int radius : {2, 3}) {
    const Stencil s = Stencil::primitive(radius);
    for (const auto& o : s.offsets()) {
      EXPECT_EQ(gcd3(o), 1);
      EXPECT_LE(std::max({std::abs(o[0]), std::abs(o[1]), std::abs(o[2])}), radius);
    }
  }
}

TEST(Stencil, RejectsBadNamesAndOffsetSets) {
  EXPECT_THROW(Stencil::byName("27"), std::invalid_argument);
  EXPECT_THROW(Stencil::byName(""), std::invalid_argument);
  EXPECT_THROW(Stencil::byName("full"), std::invalid_argument);
  EXPECT_THROW(Stencil::fromOffsets({}), std::invalid_argument);
  EXPECT_THROW(Stencil::fromOffsets({{1, 0, 0}}), std::invalid_argument);  // no (-1,0,0)
  EXPECT_THROW(Stencil::fromOffsets({{1, 2, 0}, {-1, -2, 0}, {0, 0, 1}}), std::invalid_argument);
  EXPECT_THROW(Stencil::fromOffsets({{0, 0, 0}}), std::invalid_argument);
  EXPECT_THROW(Stencil::fromOffsets({{1, 0, 0}, {-1, 0, 0}, {1, 0, 0}}), std::invalid_argument);
  EXPECT_THROW(Stencil::primitive(0), std::invalid_argument);
  const Stencil knight = Stencil::fromOffsets({{1, 2, 0}, {-1, -2, 0}});
  EXPECT_EQ(knight.size(), 2);
  EXPECT_EQ(knight.radius(), 2);
}

}  // namespace
}  // namespace stvd
