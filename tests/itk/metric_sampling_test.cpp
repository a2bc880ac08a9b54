// Log-Euclidean trilinear sampling of a voxel metric at mesh vertices.
#include <gtest/gtest.h>

#include <cmath>

#include "stvd/imaging/metric_sampling.hpp"

namespace stvd::imaging {
namespace {

GridGeometry lineOfVoxels(std::size_t n) {
  GridGeometry g;
  g.size = {n, 1, 1};
  g.spacing = {2.0, 1.0, 1.0};
  g.origin = {10.0, -3.0, 4.0};
  return g;
}

TEST(MetricSampling, ReproducesAConstantFieldAtAnyPointOfAnObliqueGrid) {
  GridGeometry g;
  g.size = {4, 3, 5};
  g.spacing = {1.0, 1.5, 0.7};
  g.origin = {-2.0, 3.0, 1.0};
  const double c = std::cos(0.4), s = std::sin(0.4);
  g.direction = {c, -s, 0, s, c, 0, 0, 0, 1};
  const SymTensor3 t{2.0f, 0.3f, -0.2f, 1.5f, 0.1f, 0.8f};
  const std::vector<SymTensor3> metric(60, t);
  const std::vector<std::uint8_t> inDomain(60, 1);
  const std::vector<Vec3d> points{g.indexToPhysicalPoint(0.3, 1.7, 2.2), g.indexToPhysicalPoint(3, 2, 4),
                                  g.indexToPhysicalPoint(-0.4, 0.1, 4.45)};
  const SampledMetric out = sampleMetricLogEuclidean(g, metric, inDomain, points);
  ASSERT_TRUE(out.outsideImage.empty());
  for (std::size_t p = 0; p < points.size(); ++p) {
    EXPECT_EQ(out.inDomain[p], 1);
    EXPECT_NEAR(out.metric[p].xx, t.xx, 1e-5);
    EXPECT_NEAR(out.metric[p].xy, t.xy, 1e-5);
    EXPECT_NEAR(out.metric[p].xz, t.xz, 1e-5);
    EXPECT_NEAR(out.metric[p].yy, t.yy, 1e-5);
    EXPECT_NEAR(out.metric[p].yz, t.yz, 1e-5);
    EXPECT_NEAR(out.metric[p].zz, t.zz, 1e-5);
  }
}

TEST(MetricSampling, InterpolatesInTheLogDomainSoTheMidpointIsTheGeometricMean) {
  const GridGeometry g = lineOfVoxels(2);
  const std::vector<SymTensor3> metric{{1.f, 0.f, 0.f, 9.f, 0.f, 1.f}, {4.f, 0.f, 0.f, 1.f, 0.f, 1.f}};
  // A quarter of the way: exp(0.75 log a + 0.25 log b).
  const SampledMetric out =
      sampleMetricLogEuclidean(g, metric, {1, 1}, {g.indexToPhysicalPoint(0.5, 0, 0), g.indexToPhysicalPoint(0.25, 0, 0)});
  EXPECT_NEAR(out.metric[0].xx, 2.0, 1e-5);  // sqrt(1 * 4), not (1 + 4) / 2
  EXPECT_NEAR(out.metric[0].yy, 3.0, 1e-5);  // sqrt(9 * 1)
  EXPECT_NEAR(out.metric[0].zz, 1.0, 1e-5);
  EXPECT_NEAR(out.metric[1].xx, std::pow(4.0, 0.25), 1e-5);
  EXPECT_NEAR(out.metric[1].yy, std::pow(9.0, 0.75), 1e-5);
}

TEST(MetricSampling, LeavesOutCornersOutsideTheDomain) {
  const GridGeometry g = lineOfVoxels(3);
  const std::vector<SymTensor3> metric{{1.f, 0.f, 0.f, 1.f, 0.f, 1.f}, {5.f, 0.f, 0.f, 1.f, 0.f, 1.f},
                                       {7.f, 0.f, 0.f, 1.f, 0.f, 1.f}};
  const SampledMetric out = sampleMetricLogEuclidean(
      g, metric, {1, 0, 0}, {g.indexToPhysicalPoint(0.3, 0, 0), g.indexToPhysicalPoint(1.5, 0, 0)});
  EXPECT_EQ(out.inDomain[0], 1);
  EXPECT_NEAR(out.metric[0].xx, 1.0, 1e-6) << "only the in-domain corner counts";
  EXPECT_EQ(out.inDomain[1], 0) << "no corner in the domain";
  EXPECT_EQ(out.metric[1].xx, 1.f) << "identity where not in the domain";
}

TEST(MetricSampling, PointsBeyondHalfAVoxelOutsideTheCentresAreOutsideTheImage) {
  const GridGeometry g = lineOfVoxels(2);
  const std::vector<SymTensor3> metric{{3.f, 0.f, 0.f, 1.f, 0.f, 1.f}, {3.f, 0.f, 0.f, 1.f, 0.f, 1.f}};
  const std::vector<Vec3d> points{g.indexToPhysicalPoint(-0.49, 0, 0), g.indexToPhysicalPoint(1.49, 0.4, -0.4),
                                  g.indexToPhysicalPoint(-0.51, 0, 0), g.indexToPhysicalPoint(0.5, 0.6, 0)};
  const SampledMetric out = sampleMetricLogEuclidean(g, metric, {1, 1}, points);
  EXPECT_EQ(out.outsideImage, (std::vector<std::size_t>{2, 3}));
  EXPECT_EQ(out.inDomain, (std::vector<std::uint8_t>{1, 1, 0, 0}));
  EXPECT_NEAR(out.metric[0].xx, 3.0, 1e-5);
}

}  // namespace
}  // namespace stvd::imaging
