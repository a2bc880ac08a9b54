// Every distance is the length of a path that lies in the domain: on a
// masked grid no edge, stencil step or STVD candidate passes through an
// excluded voxel or a gap of zero width (VoxelConnectivity).
//
// The scenes are thin walls in a slab of 1 mm voxels with the Euclidean
// metric, so that the exact distances are lengths of polygons around the
// walls, worked out below by hand. The domain's region is the union of the
// closed cells (segments, squares, cubes between voxel centres) whose
// corners are all domain voxels: a wall voxel at index x0 removes the open
// cells around it, so in the plane it is an open square (x0 - 1, x0 + 1) x
// (y0 - 1, y0 + 1) that paths go around.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

#include "method_cases.hpp"
#include "stvd/propagation.hpp"

namespace stvd {
namespace {

using test::MethodCase;

/// A slab of nx x ny x nz voxels of 1 mm with the identity metric.
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
  /// Runs one method over the slab and returns the distance at `target`.
  double distance(const std::string& stencil, const PropagationOptions& options, std::array<int, 3> source,
                  std::array<int, 3> target, VoxelConnectivity connectivity = VoxelConnectivity::Faces) const {
    const VoxelGridDomain domain(geometry, Stencil::byName(stencil), mask, connectivity);
    const RiemannianMetric metric =
        RiemannianMetric::constant(domain.vertexCount(), SymTensor3{1.f, 0.f, 0.f, 1.f, 0.f, 1.f});
    const PropagationResult r =
        propagate(domain, metric, {domain.vertexAt(source[0], source[1], source[2])}, options);
    return r.distance[domain.vertexAt(target[0], target[1], target[2])];
  }
};

const char* const kStencils[] = {"6", "18", "26", "98", "290"};

class DomainRegion : public ::testing::TestWithParam<MethodCase> {};

double length(double dx, double dy, double dz = 0.0) { return std::sqrt(dx * dx + dy * dy + dz * dz); }

TEST_P(DomainRegion, AStraightWallIsPassedOnlyAroundItsEnd) {
  // Wall x = 20, y = 0..34, through the whole slab; the gap is y = 35..39.
  // The removed region is 19 < x < 21, y < 35, so the shortest path from
  // (10, 5) to (30, 5) runs over the corners (19, 35) and (21, 35).
  Slab slab(40, 40, 3);
  for (int k = 0; k < 3; ++k)
    for (int j = 0; j <= 34; ++j) slab.exclude(20, j, k);
  const double exact = 2.0 * length(9, 30) + 2.0;  // 64.64 mm
  for (const char* stencil : kStencils) {
    const double d = slab.distance(stencil, GetParam().options(), {10, 5, 1}, {30, 5, 1});
    std::printf("[ measured ] straight wall, %s, stencil %s: %.3f mm (exact %.3f)\n", GetParam().name, stencil,
                d, exact);
    ASSERT_TRUE(std::isfinite(d)) << stencil;
    EXPECT_GE(d, exact * (1.0 - 1e-6)) << "stencil " << stencil << " passes through the wall";
  }
}

TEST_P(DomainRegion, ADiagonalWallIsClosedWithTheDefaultConnectivity) {
  // Wall voxels (i, i), i = 0..34: neighbours along it touch only along an
  // edge. The removed region is the union of the open squares (i - 1, i + 1)^2,
  // from the image's corner to (35, 35): the way from (30, 10) to (10, 30)
  // runs around the end over (35, 33), (35, 35) and (33, 35).
  Slab slab(40, 40, 3);
  for (int k = 0; k < 3; ++k)
    for (int i = 0; i <= 34; ++i) slab.exclude(i, i, k);
  const double exact = 2.0 * length(5, 23) + 4.0;  // 51.07 mm
  for (const char* stencil : kStencils) {
    const double d = slab.distance(stencil, GetParam().options(), {30, 10, 1}, {10, 30, 1});
    ASSERT_TRUE(std::isfinite(d)) << stencil;
    EXPECT_GE(d, exact * (1.0 - 1e-6)) << "stencil " << stencil << " passes between two wall voxels";
  }
}

TEST_P(DomainRegion, ConnectivityEighteenJoinsVoxelsAcrossAnEdgeContact) {
  // The same diagonal wall. With VoxelConnectivity::Edges the voxels (i + 1, i)
  // and (i, i + 1) are joined by the step between them, so the wall can be
  // crossed anywhere; the shortest crossing is (20, 19) -> (19, 20).
  Slab slab(40, 40, 3);
  for (int k = 0; k < 3; ++k)
    for (int i = 0; i <= 34; ++i) slab.exclude(i, i, k);
  const double crossing = 2.0 * length(10, 9) + std::sqrt(2.0);  // 28.32 mm
  const double around = 2.0 * length(5, 23) + 4.0;
  for (const char* stencil : {"18", "26", "98", "290"}) {
    const double d =
        slab.distance(stencil, GetParam().options(), {30, 10, 1}, {10, 30, 1}, VoxelConnectivity::Edges);
    EXPECT_GE(d, crossing * (1.0 - 1e-6)) << stencil;
    EXPECT_LT(d, around) << stencil << ": the contact was not used";
  }
}

TEST_P(DomainRegion, AOneVoxelTunnelIsFollowedAlongItsAxis) {
  // A wall ten voxels thick (x = 15..24) with one open line of voxels,
  // y = 20, z = 1, through it. Inside the wall only the segment between
  // those voxel centres lies in the domain's region.
  Slab slab(40, 40, 3);
  for (int k = 0; k < 3; ++k)
    for (int j = 0; j < 40; ++j)
      for (int i = 15; i <= 24; ++i)
        if (!(j == 20 && k == 1)) slab.exclude(i, j, k);
  const double exact = 2.0 * length(9, 10) + 11.0;  // (5, 10) -> (14, 20) -> (25, 20) -> (34, 30)
  for (const char* stencil : kStencils) {
    const double d = slab.distance(stencil, GetParam().options(), {5, 10, 1}, {34, 30, 1});
    ASSERT_TRUE(std::isfinite(d)) << stencil;
    EXPECT_GE(d, exact * (1.0 - 1e-6)) << stencil;
  }
}

TEST_P(DomainRegion, BlocksTouchingAtACornerAreJoinedOnlyWithConnectivityTwentySix) {
  // Two boxes of voxels that share one corner of their cubes: x, y <= 10,
  // z <= 1 and x, y >= 11, z >= 2. Only the step (10, 10, 1) -> (11, 11, 2)
  // joins them, and only with VoxelConnectivity::Corners.
  Slab slab(22, 22, 4);
  for (int k = 0; k < 4; ++k)
    for (int j = 0; j < 22; ++j)
      for (int i = 0; i < 22; ++i) {
        const bool low = i <= 10 && j <= 10 && k <= 1, high = i >= 11 && j >= 11 && k >= 2;
        if (!low && !high) slab.exclude(i, j, k);
      }
  const double exact = length(8, 6, 1) + std::sqrt(3.0) + length(6, 8, 1);
  for (const char* stencil : {"26", "98", "290"}) {
    for (VoxelConnectivity c : {VoxelConnectivity::Faces, VoxelConnectivity::Edges})
      EXPECT_EQ(slab.distance(stencil, GetParam().options(), {2, 4, 0}, {17, 19, 3}, c), kUnreachable)
          << stencil << ", connectivity " << static_cast<int>(c);
    const double d = slab.distance(stencil, GetParam().options(), {2, 4, 0}, {17, 19, 3}, VoxelConnectivity::Corners);
    ASSERT_TRUE(std::isfinite(d)) << stencil;
    EXPECT_GE(d, exact * (1.0 - 1e-6)) << stencil;
  }
}

TEST_P(DomainRegion, RefusedCandidatesAreCounted) {
  // Near the straight wall's end STVD's chains turn the corner, and the
  // candidates that would cut it are refused and counted.
  Slab slab(40, 40, 3);
  for (int k = 0; k < 3; ++k)
    for (int j = 0; j <= 34; ++j) slab.exclude(20, j, k);
  const VoxelGridDomain domain(slab.geometry, Stencil::full26(), slab.mask);
  const RiemannianMetric metric =
      RiemannianMetric::constant(domain.vertexCount(), SymTensor3{1.f, 0.f, 0.f, 1.f, 0.f, 1.f});
  const PropagationResult r = propagate(domain, metric, {domain.vertexAt(10, 5, 1)}, GetParam().options());
  if (GetParam().method == Method::Dijkstra)
    EXPECT_EQ(r.refusedCandidates, 0u);
  else
    EXPECT_GT(r.refusedCandidates, 0u);
}

INSTANTIATE_TEST_SUITE_P(Method, DomainRegion, ::testing::ValuesIn(test::kMethodCases), test::methodCaseName);

TEST(DomainRegion, WithoutExcludedVoxelsNothingIsChecked) {
  // A mask that keeps every voxel: the clearance is saturated, no step or
  // candidate is checked, and the result is the unmasked one bit for bit.
  Slab slab(24, 20, 16);
  const VoxelGridDomain open(slab.geometry, Stencil::full26());
  const VoxelGridDomain masked(slab.geometry, Stencil::full26(), slab.mask);
  const RiemannianMetric metric =
      RiemannianMetric::constant(open.vertexCount(), SymTensor3{2.f, 0.3f, 0.f, 1.f, -0.2f, 1.5f});
  const PropagationResult a = propagate(open, metric, {open.vertexAt(3, 4, 5)});
  const PropagationResult b = propagate(masked, metric, {masked.vertexAt(3, 4, 5)});
  EXPECT_EQ(a.distance, b.distance);
  EXPECT_EQ(b.refusedCandidates, 0u);
  for (VertexId v = 0; v < masked.vertexCount(); ++v) ASSERT_EQ(masked.clearance()[v], 255) << v;
}

TEST(DomainRegion, ClearanceIsTheChebyshevDistanceToTheNearestExcludedVoxel) {
  Slab slab(13, 11, 9);
  slab.exclude(6, 5, 4);
  slab.exclude(0, 0, 0);
  const VoxelGridDomain domain(slab.geometry, Stencil::full26(), slab.mask);
  for (int k = 0; k < 9; ++k)
    for (int j = 0; j < 11; ++j)
      for (int i = 0; i < 13; ++i) {
        const int toCentre = std::max({std::abs(i - 6), std::abs(j - 5), std::abs(k - 4)});
        const int toCorner = std::max({i, j, k});
        ASSERT_EQ(domain.clearance()[domain.vertexAt(i, j, k)], std::min(toCentre, toCorner))
            << i << " " << j << " " << k;
      }
}

}  // namespace
}  // namespace stvd
