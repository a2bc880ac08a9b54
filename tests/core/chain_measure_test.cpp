// The rules for measuring an STVD candidate (ChainMeasure).
//
// On a noisy tensor field — the strong direction drawn at random in every
// voxel, as in diffusion tensors of real tissue — no path can be shorter
// than sqrt(lambda_min) |x - s|, lambda_min the smallest eigenvalue of all
// tensors. The segment measure keeps that bound by construction: each
// sample's tensor is a convex combination of voxel tensors, whose smallest
// eigenvalue is at least lambda_min, so every candidate is at least
// sqrt(lambda_min) |E|, and the base distance obeys the bound by induction.
// LargestEdgeNorm keeps it for the same reason. The paper's
// projection-weighted rule does not: there the portions of
// backward-pointing edges cancel expensive forward ones.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <cstring>
#include <vector>

#include "exact_metrics.hpp"
#include "relative_error.hpp"
#include "method_cases.hpp"
#include "scenes.hpp"
#include "stvd/propagation/propagation.hpp"
#include "stvd/voxel_grid/voxel_grid_propagation.hpp"

namespace stvd {
namespace {

constexpr double kGamma = 10.0;  // anisotropy of every noisy tensor

/// Unit-cube grid with a uniaxial tensor of anisotropy kGamma per voxel whose
/// expensive axis is drawn uniformly on the sphere: lambda_min = 1.
struct NoisyField {
  VoxelGridDomain domain{test::obliqueGrid({36, 34, 30}), Stencil::full26()};
  RiemannianMetric metric{test::randomAxisTensors(domain.vertexCount(), kGamma, 20131122)};
  VertexId source = domain.vertexAt(18, 17, 15);
};

/// Voxels whose distance lies below sqrt(lambda_min) |x - s| (lambda_min = 1),
/// beyond float rounding.
std::size_t belowEuclideanBound(const NoisyField& f, const PropagationResult& r) {
  const Vec3d s = f.domain.physicalPoint(f.source);
  std::size_t below = 0;
  for (VertexId v = 0; v < f.domain.vertexCount(); ++v)
    below += r.distance[v] < (1.0 - 1e-5) * norm(f.domain.physicalPoint(v) - s) ? 1 : 0;
  return below;
}

PropagationOptions stvd(int k, ChainMeasure measure) {
  return test::withMethod(Method::ShortTermVectorDijkstra, k, measure);
}

TEST(ChainMeasure, LargestEdgeNormNeverGoesBelowTheEuclideanBoundOnANoisyField) {
  const NoisyField f;
  for (int k : {2, 5, 8, 16}) {
    const PropagationResult r =
        propagate(f.domain, f.metric, {f.source}, stvd(k, ChainMeasure::LargestEdgeNorm));
    EXPECT_EQ(belowEuclideanBound(f, r), 0u) << "k = " << k;
  }
}

TEST(ChainMeasure, SegmentMeasureNeverGoesBelowTheEuclideanBoundOnANoisyField) {
  const NoisyField f;
  for (int k : {2, 5, 8, 16}) {
    const PropagationResult r = propagate(f.domain, f.metric, {f.source}, stvd(k, ChainMeasure::Segment));
    EXPECT_EQ(r.finalizedVertices, f.domain.vertexCount()) << "k = " << k;
    EXPECT_EQ(belowEuclideanBound(f, r), 0u) << "k = " << k;
  }
}

// Documents the failure mode that the two other rules exist for. Measured:
// with k = 8, 36584 of the 36720 voxels fall below the bound.
TEST(ChainMeasure, ProjectionWeightedRuleCollapsesOnANoisyField) {
  const NoisyField f;
  const PropagationResult r =
      propagate(f.domain, f.metric, {f.source}, stvd(8, ChainMeasure::ProjectionWeighted));
  const std::size_t below = belowEuclideanBound(f, r);
  std::printf("[ measured ] projection rule, noisy field, k = 8: %zu of %u voxels below the bound\n",
              below, f.domain.vertexCount());
  EXPECT_GT(below, f.domain.vertexCount() / 2);
}

TEST(ChainMeasure, EveryRuleIsExactForAConstantNormAlongAStraightChain) {
  // A 1-voxel-thick line of voxels along x: every chain is straight, so both
  // rules measure ||E|| exactly and the distance is the exact one.
  GridGeometry g;
  g.size = {64, 1, 1};
  g.spacing = {0.7, 1.0, 1.0};
  const VoxelGridDomain domain(g, Stencil::full26());
  const test::Mat3 t = test::uniaxialTensor(7.0, {1.0, 2.0, 0.5});
  const auto metric = RiemannianMetric::constant(domain.vertexCount(), test::toSymTensor(t));
  for (ChainMeasure m : {ChainMeasure::Segment, ChainMeasure::ProjectionWeighted, ChainMeasure::LargestEdgeNorm}) {
    const PropagationResult r = propagate(domain, metric, {0}, stvd(8, m));
    for (VertexId v = 1; v < domain.vertexCount(); ++v) {
      const double exact = test::tensorNorm(t, domain.physicalPoint(v) - domain.physicalPoint(0));
      EXPECT_NEAR(r.distance[v], exact, 2e-6 * exact);
    }
  }
}

// Measured (x86-64-v3 build) on a 48x32x24 oblique grid, gamma 10, k = 8:
// mean 0.0084, about what the projection rule reaches on the constant metric
// specification (0.0093). Bound 1.5x.
TEST(ChainMeasure, LargestEdgeNormIsAccurateAndNeverShortForAConstantNorm) {
  const VoxelGridDomain domain(test::obliqueGrid({48, 32, 24}), Stencil::full26());
  const test::Mat3 t = test::uniaxialTensor(10.0, {0.3, -0.8, 0.5});
  const auto metric = RiemannianMetric::constant(domain.vertexCount(), test::toSymTensor(t));
  const VertexId s = domain.vertexAt(20, 15, 11);
  const PropagationResult b = propagate(domain, metric, {s}, stvd(8, ChainMeasure::LargestEdgeNorm));
  test::RelativeErrors errors;
  for (VertexId v = 0; v < domain.vertexCount(); ++v) {
    if (v == s) continue;
    const double exact = test::tensorNorm(t, domain.physicalPoint(v) - domain.physicalPoint(s));
    errors.add(b.distance[v], exact);
    EXPECT_GE(b.distance[v], exact * (1.0 - 1e-5));
  }
  test::reportMeasurement("largest edge norm, constant gamma 10, k = 8", errors);
  EXPECT_LT(errors.mean(), 0.013);
}

TEST(ChainMeasure, DepthOneIsDijkstraWithEveryRule) {
  const NoisyField f;
  const PropagationResult d = dijkstra(f.domain, f.metric, {f.source});
  for (ChainMeasure m : {ChainMeasure::Segment, ChainMeasure::ProjectionWeighted, ChainMeasure::LargestEdgeNorm}) {
    const PropagationResult s = propagate(f.domain, f.metric, {f.source}, stvd(1, m));
    EXPECT_EQ(std::memcmp(d.distance.data(), s.distance.data(), d.distance.size() * sizeof(double)), 0)
        << chainMeasureName(m);
    EXPECT_EQ(d.predecessor, s.predecessor) << chainMeasureName(m);
  }
}

}  // namespace
}  // namespace stvd
