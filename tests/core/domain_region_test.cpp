// Every distance is the length of a path that lies in the domain: on a
// masked grid no edge, stencil step or STVD candidate passes through an
// excluded voxel or a gap of zero width (VoxelConnectivity). The scenes and
// their exact distances are in wall_scenes.hpp.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

#include "method_cases.hpp"
#include "stvd/propagation/propagation.hpp"
#include "stvd/voxel_grid/voxel_grid_propagation.hpp"
#include "wall_scenes.hpp"

namespace stvd {
namespace {

using test::MethodCase;
using test::WallScene;

/// Runs one method over the scene's slab and returns the distance at its target.
double distance(const WallScene& scene, const std::string& stencil, const PropagationOptions& options,
                VoxelConnectivity connectivity = VoxelConnectivity::Faces) {
  const VoxelGridDomain domain = scene.slab.domain(Stencil::byName(stencil), connectivity);
  const PropagationResult r = propagate(domain, scene.slab.identityMetric(),
                                        {domain.vertexAt(scene.source[0], scene.source[1], scene.source[2])}, options);
  return r.distance[domain.vertexAt(scene.target[0], scene.target[1], scene.target[2])];
}

const char* const kStencils[] = {"6", "18", "26", "98", "290"};

class DomainRegion : public ::testing::TestWithParam<MethodCase> {};

TEST_P(DomainRegion, AStraightWallIsPassedOnlyAroundItsEnd) {
  const WallScene scene = test::straightWallWithGap();
  const double exact = scene.faces;  // 64.64 mm
  for (const char* stencil : kStencils) {
    const double d = distance(scene, stencil, GetParam().options());
    std::printf("[ measured ] straight wall, %s, stencil %s: %.3f mm (exact %.3f)\n", GetParam().name, stencil,
                d, exact);
    ASSERT_TRUE(std::isfinite(d)) << stencil;
    EXPECT_GE(d, exact * (1.0 - 1e-6)) << "stencil " << stencil << " passes through the wall";
  }
}

TEST_P(DomainRegion, ADiagonalWallIsClosedWithTheDefaultConnectivity) {
  const WallScene scene = test::diagonalWall();
  const double exact = scene.faces;  // 51.07 mm, around the wall's end
  for (const char* stencil : kStencils) {
    const double d = distance(scene, stencil, GetParam().options());
    ASSERT_TRUE(std::isfinite(d)) << stencil;
    EXPECT_GE(d, exact * (1.0 - 1e-6)) << "stencil " << stencil << " passes between two wall voxels";
  }
}

TEST_P(DomainRegion, ConnectivityEighteenJoinsVoxelsAcrossAnEdgeContact) {
  // The same diagonal wall, crossed between two wall voxels.
  const WallScene scene = test::diagonalWall();
  const double crossing = scene.edges;  // 28.32 mm
  const double around = scene.faces;
  for (const char* stencil : {"18", "26", "98", "290"}) {
    const double d = distance(scene, stencil, GetParam().options(), VoxelConnectivity::Edges);
    EXPECT_GE(d, crossing * (1.0 - 1e-6)) << stencil;
    EXPECT_LT(d, around) << stencil << ": the contact was not used";
  }
}

TEST_P(DomainRegion, AOneVoxelTunnelIsFollowedAlongItsAxis) {
  const WallScene scene = test::oneVoxelTunnel();
  const double exact = scene.faces;  // 37.90 mm
  for (const char* stencil : kStencils) {
    const double d = distance(scene, stencil, GetParam().options());
    ASSERT_TRUE(std::isfinite(d)) << stencil;
    EXPECT_GE(d, exact * (1.0 - 1e-6)) << stencil;
  }
}

TEST_P(DomainRegion, BlocksTouchingAtACornerAreJoinedOnlyWithConnectivityTwentySix) {
  const WallScene scene = test::blocksTouchingAtACorner();
  const double exact = scene.corners;
  for (const char* stencil : {"26", "98", "290"}) {
    for (VoxelConnectivity c : {VoxelConnectivity::Faces, VoxelConnectivity::Edges})
      EXPECT_EQ(distance(scene, stencil, GetParam().options(), c), kUnreachable)
          << stencil << ", connectivity " << static_cast<int>(c);
    const double d = distance(scene, stencil, GetParam().options(), VoxelConnectivity::Corners);
    ASSERT_TRUE(std::isfinite(d)) << stencil;
    EXPECT_GE(d, exact * (1.0 - 1e-6)) << stencil;
  }
}

TEST_P(DomainRegion, ConnectivitiesEighteenAndTwentySixKeepToTheirRegionInEveryScene) {
  // The exact distances of wall_scenes.hpp per connectivity: 18 and 26 also
  // join diagonal steps past a wall's end and into a tunnel (6: the tests
  // above).
  for (const WallScene& scene : test::wallScenes())
    for (VoxelConnectivity c : {VoxelConnectivity::Edges, VoxelConnectivity::Corners})
      for (const char* stencil : kStencils) {
        const double d = distance(scene, stencil, GetParam().options(), c);
        const double exact = scene.exact(c);
        if (exact == kUnreachable) {
          EXPECT_EQ(d, kUnreachable) << scene.name << ", stencil " << stencil;
          continue;
        }
        EXPECT_GE(d, exact * (1.0 - 1e-6)) << scene.name << ", connectivity " << static_cast<int>(c)
                                           << ", stencil " << stencil;
      }
}

TEST_P(DomainRegion, RefusedCandidatesAreCounted) {
  // Near the straight wall's end STVD's chains turn the corner, and the
  // candidates that would cut it are refused and counted.
  const WallScene scene = test::straightWallWithGap();
  const VoxelGridDomain domain = scene.slab.domain(Stencil::full26());
  const PropagationResult r = propagate(domain, scene.slab.identityMetric(), {domain.vertexAt(10, 5, 1)},
                                        GetParam().options());
  if (GetParam().method == Method::Dijkstra)
    EXPECT_EQ(r.refusedCandidates, 0u);
  else
    EXPECT_GT(r.refusedCandidates, 0u);
}

INSTANTIATE_TEST_SUITE_P(Method, DomainRegion, ::testing::ValuesIn(test::kMethodCases), test::methodCaseName);

TEST(DomainRegion, WithoutExcludedVoxelsNothingIsChecked) {
  // A mask that keeps every voxel: the clearance is saturated, no step or
  // candidate is checked, and the result is the unmasked one bit for bit.
  const test::Slab slab(24, 20, 16);
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
  test::Slab slab(13, 11, 9);
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
