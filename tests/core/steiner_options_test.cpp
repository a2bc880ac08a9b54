// Steiner propagation's inputs and stop conditions: bad input is refused
// with std::invalid_argument, and the maximum distance, targets, several
// sources and cancellation behave as they do for the other methods.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <vector>

#include "exact_metrics.hpp"
#include "scenes.hpp"
#include "stvd/lanthier/lanthier_propagation.hpp"
#include "stvd/voxel_grid/voxel_grid_lanthier.hpp"

namespace stvd {
namespace {

struct SmallGrid {
  VoxelGridDomain domain{test::obliqueGrid({9, 8, 7}), Stencil::full26()};
  RiemannianMetric metric{test::smoothVaryingTensors(domain)};
};

LanthierOptions withSteinerPoints(int m) {
  LanthierOptions o;
  o.steinerPoints = m;
  return o;
}

TEST(SteinerInput, RefusesWhatCannotBeComputed) {
  const SmallGrid s;
  const VertexId v = s.domain.vertexAt(4, 4, 3);
  auto run = [&](const std::vector<VertexId>& sources, const LanthierOptions& o) {
    return lanthierPropagate(s.domain, s.metric, sources, o);
  };
  EXPECT_THROW(run({}, {}), std::invalid_argument);
  EXPECT_THROW(run({s.domain.vertexCount()}, {}), std::invalid_argument);
  EXPECT_THROW(run({v}, withSteinerPoints(0)), std::invalid_argument);
  EXPECT_THROW(run({v}, withSteinerPoints(kMaxSteinerPoints + 1)), std::invalid_argument);
  LanthierOptions nan;
  nan.maxDistance = std::numeric_limits<double>::quiet_NaN();
  EXPECT_THROW(run({v}, nan), std::invalid_argument);
  LanthierOptions badTarget;
  badTarget.targets = {s.domain.vertexCount() + 3};
  EXPECT_THROW(run({v}, badTarget), std::invalid_argument);
  const RiemannianMetric small = RiemannianMetric::constant(10, test::toSymTensor(test::Mat3{}));
  EXPECT_THROW(lanthierPropagate(s.domain, small, {v}), std::invalid_argument);

  // A source outside the mask.
  std::vector<std::uint8_t> mask(s.domain.vertexCount(), 1);
  mask[v] = 0;
  const VoxelGridDomain masked(s.domain.geometry(), Stencil::full26(), mask);
  EXPECT_THROW(lanthierPropagate(masked, s.metric, {v}), std::invalid_argument);
}

/// Masked voxels carry no Steiner points: masking the last slice of a grid
/// gives exactly the graph and the distances of the grid without that slice
/// (the domain's voxels are numbered in index order, as the smaller grid's).
TEST(SteinerInput, MaskedVoxelsCarryNoPoints) {
  const SmallGrid s;
  std::vector<std::uint8_t> mask(s.domain.vertexCount(), 1);
  for (int j = 0; j < 8; ++j)
    for (int i = 0; i < 9; ++i) mask[s.domain.vertexAt(i, j, 6)] = 0;
  const VoxelGridDomain masked(s.domain.geometry(), Stencil::full26(), mask);
  GridGeometry shorter = s.domain.geometry();
  shorter.size[2] = 6;
  const VoxelGridDomain cut(shorter, Stencil::full26());
  const RiemannianMetric cutMetric(std::vector<SymTensor3>(s.metric.params().begin(),
                                                           s.metric.params().begin() + cut.vertexCount()));
  const VertexId source = s.domain.vertexAt(2, 3, 3);
  ASSERT_EQ(cut.vertexAt(2, 3, 3), source);
  LanthierOptions o = withSteinerPoints(2);
  o.keepPointDistances = true;
  const LanthierResult a = lanthierPropagate(masked, s.metric, {source}, o);
  const LanthierResult b = lanthierPropagate(cut, cutMetric, {source}, o);
  EXPECT_EQ(a.graphPoints, 19u * cut.vertexCount());
  EXPECT_EQ(a.graphPoints, b.graphPoints);
  EXPECT_EQ(a.pointDistance, b.pointDistance);
  EXPECT_EQ(a.relaxedEdges, b.relaxedEdges);
  for (VertexId v = 0; v < cut.vertexCount(); ++v) ASSERT_EQ(a.distance[v], b.distance[v]) << "voxel " << v;
  for (VertexId v = cut.vertexCount(); v < masked.vertexCount(); ++v) EXPECT_EQ(a.distance[v], kUnreachable);
  for (SteinerPointId p = 0; p < a.graphPoints; p += 7)
    EXPECT_LT(norm(steinerPointPosition(masked, 2, p) - steinerPointPosition(cut, 2, p)), 1e-9) << "point " << p;
  EXPECT_EQ(a.peakStateBytes, b.peakStateBytes);
}

TEST(SteinerInput, VoxelWithoutADomainNeighbourAlongAnAxisIsReachedOnlyAsASource) {
  // Voxel (4, 4, 3) is in the mask, but its six neighbours are not, so no
  // edge, square or cube around it is a cell (and the default connectivity
  // joins no diagonal).
  const SmallGrid s;
  std::vector<std::uint8_t> mask(s.domain.vertexCount(), 1);
  const int off[6][3] = {{1, 0, 0}, {-1, 0, 0}, {0, 1, 0}, {0, -1, 0}, {0, 0, 1}, {0, 0, -1}};
  for (const auto& o : off) mask[s.domain.vertexAt(4 + o[0], 4 + o[1], 3 + o[2])] = 0;
  const VoxelGridDomain masked(s.domain.geometry(), Stencil::full26(), mask);
  const VertexId isolated = masked.vertexAt(4, 4, 3), other = masked.vertexAt(0, 0, 0);
  const LanthierResult fromOther = lanthierPropagate(masked, s.metric, {other}, withSteinerPoints(2));
  EXPECT_EQ(fromOther.distance[isolated], kUnreachable);
  EXPECT_TRUE(std::isfinite(fromOther.distance[masked.vertexAt(8, 7, 6)]));
  const LanthierResult fromIsolated = lanthierPropagate(masked, s.metric, {isolated}, withSteinerPoints(2));
  EXPECT_EQ(fromIsolated.distance[isolated], 0.0);
  EXPECT_EQ(fromIsolated.finalizedVertices, 1u);
}

TEST(SteinerStop, MaximumDistanceKeepsEveryDistanceUpToIt) {
  const SmallGrid s;
  const VertexId source = s.domain.vertexAt(2, 3, 3);
  const LanthierResult full = lanthierPropagate(s.domain, s.metric, {source}, withSteinerPoints(2));
  std::vector<double> sorted = full.distance;
  std::sort(sorted.begin(), sorted.end());
  LanthierOptions o = withSteinerPoints(2);
  o.maxDistance = sorted[sorted.size() / 2];
  const LanthierResult cut = lanthierPropagate(s.domain, s.metric, {source}, o);
  EXPECT_EQ(cut.termination, Termination::MaxDistanceReached);
  for (VertexId v = 0; v < s.domain.vertexCount(); ++v) {
    if (full.distance[v] <= o.maxDistance)
      EXPECT_EQ(cut.distance[v], full.distance[v]) << "vertex " << v;
    else
      EXPECT_EQ(cut.distance[v], kUnreachable) << "vertex " << v;
  }
}

TEST(SteinerStop, TargetsStopThePropagationOnceAllAreFinal) {
  const SmallGrid s;
  const VertexId source = s.domain.vertexAt(1, 1, 1);
  const LanthierResult full = lanthierPropagate(s.domain, s.metric, {source}, withSteinerPoints(2));
  LanthierOptions o = withSteinerPoints(2);
  o.targets = {s.domain.vertexAt(3, 2, 2), s.domain.vertexAt(2, 4, 1)};
  const LanthierResult r = lanthierPropagate(s.domain, s.metric, {source}, o);
  EXPECT_EQ(r.termination, Termination::TargetsReached);
  for (const VertexId t : o.targets) EXPECT_EQ(r.distance[t], full.distance[t]);
  EXPECT_LT(r.finalizedVertices, full.finalizedVertices);
  EXPECT_EQ(r.distance[s.domain.vertexAt(8, 7, 6)], kUnreachable);
}

TEST(SteinerStop, SeveralSourcesGiveTheMinimumOfTheSingleSourceFields) {
  const SmallGrid s;
  const VertexId a = s.domain.vertexAt(1, 1, 1), b = s.domain.vertexAt(7, 6, 5);
  const LanthierResult both = lanthierPropagate(s.domain, s.metric, {a, b}, withSteinerPoints(2));
  const LanthierResult fromA = lanthierPropagate(s.domain, s.metric, {a}, withSteinerPoints(2));
  const LanthierResult fromB = lanthierPropagate(s.domain, s.metric, {b}, withSteinerPoints(2));
  for (VertexId v = 0; v < s.domain.vertexCount(); ++v)
    EXPECT_EQ(both.distance[v], std::min(fromA.distance[v], fromB.distance[v])) << "vertex " << v;
}

TEST(SteinerStop, ProgressCallbackCanCancelAndACancelledRunHoldsNoDistances) {
  // 14^3 voxels with 61 graph points each; a report every 1024 points (the
  // interval made zero), cancelled at the third.
  const VoxelGridDomain domain(test::obliqueGrid({14, 14, 14}), Stencil::full26());
  const RiemannianMetric metric = RiemannianMetric::constant(domain.vertexCount(), test::toSymTensor(test::Mat3{}));
  LanthierOptions o = withSteinerPoints(4);
  o.progressInterval = 0.0;
  int calls = 0;
  o.progress = [&calls](const PropagationProgress& p) {
    // Voxels, not graph points: 1024 points hold about 1024 / 61 voxels.
    EXPECT_EQ(p.domainVertices, 14u * 14u * 14u);
    EXPECT_LE(p.finalizedVertices, 1024u * static_cast<unsigned>(calls) / 20);
    return ++calls < 3;
  };
  const LanthierResult r = lanthierPropagate(domain, metric, {0}, o);
  EXPECT_EQ(r.termination, Termination::Cancelled);
  EXPECT_EQ(calls, 3);
  EXPECT_LT(r.finalizedVertices, domain.vertexCount());
  for (double d : r.distance) ASSERT_EQ(d, kUnreachable);
}

}  // namespace
}  // namespace stvd
