// A stencil step longer than one voxel step (the 98- and 290-neighbourhoods)
// is measured along itself, one sample per voxel step, by every method:
// measured with the edge rule of its two end points it would pass the voxels
// between them for the price of its ends, and a distance could come out
// shorter than any path through the metric field
// (VoxelGridCandidatePath::measuresLongSteps).
#include <gtest/gtest.h>

#include <cmath>
#include <string>
#include <vector>

#include "scenes.hpp"
#include "stvd/propagation/propagation.hpp"
#include "stvd/voxel_grid/voxel_grid_propagation.hpp"

namespace stvd {
namespace {

constexpr double kGamma = 10.0;
constexpr int kWall = 7;    // the index plane i = 7 holds the expensive voxels
constexpr int kSource = 3;  // the seed's i

// Isotropic: G = I, and G = gamma^2 I in the wall, on an oblique grid whose
// spacing along i is 1 mm.
RiemannianMetric wallMetric(const VoxelGridDomain& domain) {
  std::vector<SymTensor3> tensors(domain.vertexCount());
  for (VertexId v = 0; v < domain.vertexCount(); ++v) {
    const float g = domain.indexOf(v).i == kWall ? static_cast<float>(kGamma * kGamma) : 1.f;
    tensors[v] = SymTensor3{g, 0.f, 0.f, g, 0.f, g};
  }
  return RiemannianMetric(std::move(tensors));
}

// No path from the seed to a voxel at i >= kWall + 1 is shorter than this:
// it moves at least |di| mm along the i axis, and where the interpolated
// metric rises to the wall (kWall - 1 < i < kWall + 1, a linear hat in i of
// the isotropic factor) each millimetre along i costs at least
// sqrt(1 + (gamma^2 - 1) (1 - |i - kWall|)); that slab costs at least
// 2 * integral_0^1 sqrt(1 + (gamma^2 - 1) t) dt = 4/3 (gamma^3 - 1) / (gamma^2 - 1).
double lowerBound(int i) {
  const double slab = 4.0 / 3.0 * (kGamma * kGamma * kGamma - 1.0) / (kGamma * kGamma - 1.0);
  return (kWall - 1 - kSource) + slab + (i - (kWall + 1));
}

void expectNoDistanceBelowTheWallsPrice(const Stencil& stencil, const std::string& name) {
  const VoxelGridDomain domain(test::obliqueGrid({14, 7, 7}), stencil);
  const RiemannianMetric metric = wallMetric(domain);
  const VertexId seed = domain.vertexAt(kSource, 3, 3);
  for (const bool stvd : {false, true}) {
    const PropagationResult r =
        stvd ? shortTermVectorDijkstra(domain, metric, {seed}, kDefaultMemoryDepth) : dijkstra(domain, metric, {seed});
    double lowestRatio = 1e30;
    int checked = 0;
    for (VertexId v = 0; v < domain.vertexCount(); ++v) {
      const int i = domain.indexOf(v).i;
      if (i < kWall + 1) continue;
      ++checked;
      lowestRatio = std::min(lowestRatio, r.distance[v] / lowerBound(i));
    }
    EXPECT_GT(checked, 200);
    EXPECT_GE(lowestRatio, 1.0 - 1e-6) << name << (stvd ? ", STVD" : ", Dijkstra")
                                        << ": a distance beyond the wall is below every path's length";
  }
}

TEST(LongStencilSteps, NoMethodPassesAnExpensiveVoxelForThePriceOfTheStepsEnds) {
  // Measured with the edge rule of its end points, a step over the wall
  // (from i = 6 to i = 8 or 9) cost what its cheap ends cost: beyond the
  // wall the 98-neighbourhood gave 0.334 of the bound and the
  // 290-neighbourhood 0.325, with Dijkstra and with STVD.
  expectNoDistanceBelowTheWallsPrice(Stencil::full26(), "26-neighbourhood");
  expectNoDistanceBelowTheWallsPrice(Stencil::primitive(2), "98-neighbourhood");
  expectNoDistanceBelowTheWallsPrice(Stencil::primitive(3), "290-neighbourhood");
}

TEST(LongStencilSteps, AConstantMetricStaysExactAlongEveryStep) {
  // One sample per voxel step of a constant metric is the exact length: the
  // 290-neighbourhood's Dijkstra is exact at every voxel that a single step
  // of the stencil reaches from the seed.
  const VoxelGridDomain domain(test::obliqueGrid({9, 9, 9}), Stencil::primitive(3));
  const SymTensor3 g = test::toSymTensor(test::uniaxialTensor(6.0, {1.0, 2.0, 3.0}));
  const RiemannianMetric metric = RiemannianMetric::constant(domain.vertexCount(), g);
  const VertexId seed = domain.vertexAt(4, 4, 4);
  const PropagationResult r = dijkstra(domain, metric, {seed});
  int checked = 0;
  domain.forEachNeighbor(seed, [&](VertexId w, Vec3f e) {
    const double exact = std::sqrt(static_cast<double>(g.quadraticForm(e)));
    EXPECT_NEAR(r.distance[w], exact, 2e-6 * exact);
    ++checked;
  });
  EXPECT_EQ(checked, 290);
}

}  // namespace
}  // namespace stvd
