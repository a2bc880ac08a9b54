// Every long operation reports to one Interrupter and can be stopped
// (system/interrupter.hpp, docs/library.md "Progress and cancellation"):
// start(name), 0 % first, percents that never decrease, 100 % last, end();
// stopped at its first report after the start, it ends at once with the
// result its documentation states. The report interval is made zero so
// that even these small scenes report during their work (a report every
// 1024 steps); the work done is counted, never timed.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <atomic>
#include <cmath>
#include <cstdint>
#include <vector>

#include "interrupt_recorder.hpp"
#include "scenes.hpp"
#include "stvd/cell_mesh/cell_mesh_lanthier.hpp"
#include "stvd/cell_mesh/tetrahedral_cells.hpp"
#include "stvd/lanthier/lanthier_propagation.hpp"
#include "stvd/propagation/propagation.hpp"
#include "stvd/voxel_grid/path_refinement.hpp"
#include "stvd/voxel_grid/path_tracing.hpp"
#include "stvd/voxel_grid/region_connectivity.hpp"
#include "stvd/voxel_grid/voxel_grid_lanthier.hpp"
#include "stvd/voxel_grid/voxel_grid_propagation.hpp"

namespace stvd {
namespace {

using testing::expectCompleteReports;
using testing::InterruptRecorder;

/// A ball of about 9,200 voxels in a 28^3 grid: masked, so every pass of the
/// Steiner cells' setup runs.
struct MaskedBall {
  GridGeometry geometry = test::obliqueGrid({28, 28, 28});
  VoxelGridDomain domain{geometry, Stencil::full26(), test::ballMask(geometry, {13.5, 13.5, 13.5}, 13.0)};
  RiemannianMetric metric{test::smoothVaryingTensors(domain), &domain.mask()};
  VertexId source = domain.vertexAt(14, 14, 14);
};

LanthierOptions steinerOptions(int m, Interrupter* interrupter) {
  LanthierOptions o;
  o.steinerPoints = m;
  o.interrupter = interrupter;
  o.progressInterval = 0.0;
  return o;
}

// The Steiner cells and the propagation's state are set up before the
// propagation starts: an operation of its own, which reports and ends
// before "Steiner-point propagation" starts.
TEST(LanthierSetupInterruption, TheSetupReportsZeroToHundredPercentBeforeThePropagationStarts) {
  const MaskedBall s;
  InterruptRecorder recorder;
  const LanthierResult r = lanthierPropagate(s.domain, s.metric, {s.source}, steinerOptions(4, &recorder));
  EXPECT_EQ(r.termination, Termination::Completed);
  ASSERT_EQ(recorder.operations().size(), 2u);
  EXPECT_EQ(recorder.operations()[0].name, "Steiner cells");
  EXPECT_EQ(recorder.operations()[1].name, "Steiner-point propagation");
  // 6 passes over 28^3 voxels and 2 arrays of 61 entries per domain voxel:
  // a report at least every 1024 steps of them.
  EXPECT_GT(recorder.operations()[0].percents.size(), 6u * 28 * 28 * 28 / 1024);
  for (const InterruptRecorder::Operation& o : recorder.operations()) expectCompleteReports(o);
  EXPECT_TRUE(recorder.allEnded());
}

// Stopped at its first report after the start, the setup ends there: the
// run returns Termination::Cancelled with no distances, no point was
// finalised, the propagation never started, and nothing reported again.
TEST(LanthierSetupInterruption, StoppedDuringTheSetupTheRunIsCancelledBeforeAnyPointIsFinal) {
  const MaskedBall s;
  InterruptRecorder recorder;
  recorder.stopAtFirstReportAfterStart("Steiner cells");
  const LanthierResult r = lanthierPropagate(s.domain, s.metric, {s.source}, steinerOptions(4, &recorder));
  EXPECT_EQ(r.termination, Termination::Cancelled);
  EXPECT_EQ(r.finalizedVertices, 0u);
  EXPECT_EQ(r.relaxedEdges, 0u);
  ASSERT_EQ(r.distance.size(), s.domain.vertexCount());
  for (VertexId v = 0; v < s.domain.vertexCount(); ++v) {
    ASSERT_EQ(r.distance[v], kUnreachable) << "vertex " << v;
    ASSERT_EQ(r.predecessor[v], kNoVertex) << "vertex " << v;
  }
  ASSERT_EQ(recorder.operations().size(), 1u);  // no propagation
  const InterruptRecorder::Operation& setup = recorder.operations()[0];
  EXPECT_EQ(setup.name, "Steiner cells");
  // Stopped after the first 1024 of about 1.5 million steps.
  ASSERT_EQ(setup.percents.size(), 2u);
  EXPECT_EQ(setup.percents[0], 0);
  EXPECT_EQ(setup.percents[1], 0);
  EXPECT_TRUE(setup.ended);
  EXPECT_EQ(recorder.reportsAfterStop(), 0u);
}

// The progress callback hears the setup's reports as the run's first ones
// (no vertex final, fraction 0): a host with only the callback (the tool's
// bar, the Python package) can cancel during the setup too.
TEST(LanthierSetupInterruption, TheProgressCallbackCanCancelDuringTheSetup) {
  const MaskedBall s;
  LanthierOptions o = steinerOptions(4, nullptr);
  std::vector<PropagationProgress> reports;
  o.progress = [&reports](const PropagationProgress& p) {
    reports.push_back(p);
    return reports.size() < 2;
  };
  const LanthierResult r = lanthierPropagate(s.domain, s.metric, {s.source}, o);
  EXPECT_EQ(r.termination, Termination::Cancelled);
  EXPECT_EQ(r.finalizedVertices, 0u);
  ASSERT_EQ(reports.size(), 2u);
  for (const PropagationProgress& p : reports) {
    EXPECT_EQ(p.finalizedVertices, 0u);
    EXPECT_EQ(p.fraction, 0.0);
    EXPECT_EQ(p.domainVertices, s.domain.domainVertexCount());
  }
}

// On a tetrahedral mesh the setup is the propagation's state (the cells are
// the TetrahedralCells' own): the same reports, the same cancel.
TEST(LanthierSetupInterruption, OnATetrahedralMeshTheSetupReportsAndStops) {
  const test::TetrahedralBox box = test::kuhnTetrahedralBox({6, 6, 6}, {1.0, 1.0, 1.0}, 0.0, 1);
  const TetrahedralCells cells(box.points, box.tets);
  const RiemannianMetric metric = RiemannianMetric::constant(cells.vertexCount(), test::toSymTensor(test::Mat3{}));
  InterruptRecorder all;
  EXPECT_EQ(lanthierPropagate(cells, metric, {0}, steinerOptions(4, &all)).termination, Termination::Completed);
  ASSERT_EQ(all.operations().size(), 2u);
  EXPECT_EQ(all.operations()[0].name, "Steiner cells");
  for (const InterruptRecorder::Operation& o : all.operations()) expectCompleteReports(o);

  InterruptRecorder stopping;
  stopping.stopAtFirstReportAfterStart("Steiner cells");
  const LanthierResult r = lanthierPropagate(cells, metric, {0}, steinerOptions(4, &stopping));
  EXPECT_EQ(r.termination, Termination::Cancelled);
  EXPECT_EQ(r.finalizedVertices, 0u);
  for (double d : r.distance) ASSERT_EQ(d, kUnreachable);
  EXPECT_EQ(stopping.operations().size(), 1u);
  EXPECT_EQ(stopping.reportsAfterStop(), 0u);
}

/// A path around a wall: the descent falls back to the predecessor chain
/// at its end and the refinement has corners to straighten.
struct WallWithHole {
  GridGeometry geometry = [] {
    GridGeometry g;
    g.size = {30, 30, 20};
    g.spacing = {1.0, 1.0, 1.5};
    return g;
  }();
  std::vector<std::uint8_t> mask = [this] {
    std::vector<std::uint8_t> m(geometry.voxelCount(), 1);
    for (int k = 0; k < 20; ++k)
      for (int j = 0; j < 30; ++j)
        if (!(j >= 21 && j <= 23 && k >= 9 && k <= 11)) m[15 + 30 * (j + 30 * k)] = 0;
    return m;
  }();
  VoxelGridDomain domain{geometry, Stencil::full26(), mask};
  RiemannianMetric metric{test::smoothVaryingTensors(domain), &mask};
  VertexId source = domain.vertexAt(4, 8, 10), target = domain.vertexAt(26, 8, 10);
  PropagationResult result = propagate(domain, metric, {source});
};

PathTracingOptions tracingOptions(Interrupter* interrupter) {
  PathTracingOptions o;
  o.interrupter = interrupter;
  o.progressInterval = 0.0;
  return o;
}

// Tracing a path is one operation, "path tracing": the descent reports the
// first half (how far the distance has come down), the refinement the
// second (its iterations).
TEST(PathTracingInterruption, TracingAndRefiningReportZeroToHundredPercent) {
  const WallWithHole s;
  InterruptRecorder recorder;
  const TracedPath path = traceGeodesicPath(s.domain, s.metric, s.result, s.target, tracingOptions(&recorder));
  ASSERT_FALSE(path.points.empty());
  ASSERT_GT(path.refinement.iterations, 0u);
  ASSERT_EQ(recorder.operations().size(), 1u);
  const InterruptRecorder::Operation& o = recorder.operations()[0];
  EXPECT_EQ(o.name, "path tracing");
  expectCompleteReports(o);
  // Reports from the descent (below 50 %) and from the refinement (one per
  // iteration at least).
  EXPECT_GE(std::count_if(o.percents.begin(), o.percents.end(), [](int p) { return p > 0 && p < 50; }), 1);
  EXPECT_GE(static_cast<std::size_t>(std::count_if(o.percents.begin(), o.percents.end(),
                                                   [](int p) { return p >= 50 && p < 100; })),
            path.refinement.iterations);
  // The same path as without an interrupter.
  const TracedPath plain = traceGeodesicPath(s.domain, s.metric, s.result, s.target);
  ASSERT_EQ(plain.points.size(), path.points.size());
  for (std::size_t n = 0; n < path.points.size(); ++n) EXPECT_EQ(norm(plain.points[n] - path.points[n]), 0.0);
}

// Stopped at its first report after the start (64 steps into the descent),
// the tracing throws Cancelled: a path that does not reach a source is no
// path.
TEST(PathTracingInterruption, StoppedTheTracingThrowsCancelledWithoutAPath) {
  const WallWithHole s;
  InterruptRecorder recorder;
  recorder.stopAtFirstReportAfterStart();
  EXPECT_THROW(traceGeodesicPath(s.domain, s.metric, s.result, s.target, tracingOptions(&recorder)), Cancelled);
  ASSERT_EQ(recorder.operations().size(), 1u);
  const InterruptRecorder::Operation& o = recorder.operations()[0];
  ASSERT_EQ(o.percents.size(), 2u);
  EXPECT_LT(o.percents[1], 50);  // still descending: no refinement ran
  EXPECT_TRUE(o.ended);
  EXPECT_EQ(recorder.reportsAfterStop(), 0u);
}

// Refinement on its own is "path refinement"; stopped, it throws Cancelled
// and leaves the points as they were.
TEST(PathTracingInterruption, RefinementReportsAndStoppedLeavesThePointsAsTheyWere) {
  const WallWithHole s;
  PathTracingOptions unrefined;
  unrefined.refine = false;
  const std::vector<Vec3d> traced = traceGeodesicPath(s.domain, s.metric, s.result, s.target, unrefined).points;
  ASSERT_GT(traced.size(), 2u);

  InterruptRecorder all;
  PathRefinementOptions o;
  o.interrupter = &all;
  o.progressInterval = 0.0;
  std::vector<Vec3d> refined = traced;
  const PathRefinementReport report = refineGeodesicPath(s.domain, s.metric, s.result.distance, refined, o);
  ASSERT_GT(report.iterations, 0u);
  ASSERT_EQ(all.operations().size(), 1u);
  EXPECT_EQ(all.operations()[0].name, "path refinement");
  expectCompleteReports(all.operations()[0]);
  EXPECT_GT(all.operations()[0].percents.size(), report.iterations);

  InterruptRecorder stopping;
  stopping.stopAtFirstReportAfterStart();
  o.interrupter = &stopping;
  std::vector<Vec3d> points = traced;
  EXPECT_THROW(refineGeodesicPath(s.domain, s.metric, s.result.distance, points, o), Cancelled);
  ASSERT_EQ(points.size(), traced.size());
  for (std::size_t n = 0; n < points.size(); ++n) EXPECT_EQ(norm(points[n] - traced[n]), 0.0) << "point " << n;
  // Stopped before its first iteration.
  EXPECT_EQ(stopping.operations()[0].percents, (std::vector<int>{0, 0}));
  EXPECT_EQ(stopping.reportsAfterStop(), 0u);
}

/// Four regions of 8 voxels (2 x 2 x 2 blocks) in a 24 x 20 x 16 grid under
/// a smoothly varying metric.
struct FourRegions {
  VoxelGridDomain domain{test::obliqueGrid({24, 20, 16}), Stencil::full26()};
  RiemannianMetric metric{test::smoothVaryingTensors(domain)};
  std::vector<std::vector<VertexId>> regions = [this] {
    std::vector<std::vector<VertexId>> r;
    for (const std::array<int, 3>& c : {std::array<int, 3>{2, 2, 2}, {20, 3, 4}, {4, 16, 12}, {19, 15, 13}}) {
      r.emplace_back();
      for (int k = 0; k < 2; ++k)
        for (int j = 0; j < 2; ++j)
          for (int i = 0; i < 2; ++i) r.back().push_back(domain.vertexAt(c[0] + i, c[1] + j, c[2] + k));
    }
    return r;
  }();
};

PropagationOptions propagationOptions(Interrupter* interrupter) {
  PropagationOptions o;
  o.interrupter = interrupter;
  o.progressInterval = 0.0;
  return o;
}

// The run is one operation, "region connectivity", by the share of pairs
// measured; each region's propagation and each pair's path report within
// it as operations of their own.
TEST(RegionConnectivityInterruption, TheRunAndEveryPropagationAndPathReportZeroToHundredPercent) {
  const FourRegions s;
  InterruptRecorder recorder;
  const RegionConnectivity table = regionConnectivity(s.domain, s.metric, s.regions, propagationOptions(&recorder), 1);
  for (std::size_t a = 0; a < 4; ++a)
    for (std::size_t b = 0; b < 4; ++b)
      if (a != b) {
        EXPECT_TRUE(std::isfinite(table(a, b).geodesic)) << a << " to " << b;
      }
  ASSERT_EQ(recorder.named("region connectivity").size(), 1u);
  EXPECT_EQ(recorder.operations().front().name, "region connectivity");
  EXPECT_EQ(recorder.named("propagation").size(), 4u);
  EXPECT_EQ(recorder.named("path tracing").size(), 12u);
  for (const InterruptRecorder::Operation& o : recorder.operations()) expectCompleteReports(o);
  // A report after every region and every pair: 16 steps.
  EXPECT_EQ(recorder.named("region connectivity")[0].percents.size(), 2u + 16u);
  EXPECT_TRUE(recorder.allEnded());
}

// Stopped at its first report after the start (once the first region's
// propagation is done), the run throws Cancelled: no other region is
// propagated, no path traced, and nothing reports again.
TEST(RegionConnectivityInterruption, StoppedTheRunThrowsCancelledAndDoesNoMoreWork) {
  const FourRegions s;
  InterruptRecorder recorder;
  recorder.stopAtFirstReportAfterStart("region connectivity");
  EXPECT_THROW(regionConnectivity(s.domain, s.metric, s.regions, propagationOptions(&recorder), 1), Cancelled);
  EXPECT_EQ(recorder.named("propagation").size(), 1u);
  EXPECT_EQ(recorder.named("path tracing").size(), 0u);
  EXPECT_EQ(recorder.named("region connectivity")[0].percents, (std::vector<int>{0, 6}));  // 1 of 16 steps
  EXPECT_EQ(recorder.reportsAfterStop(), 0u);
  EXPECT_TRUE(recorder.allEnded());
}

// A propagation cancelled by its progress callback cancels the run (on two
// threads): a table whose rows are missing would read as regions that do
// not reach each other.
TEST(RegionConnectivityInterruption, APropagationCancelledByItsCallbackCancelsTheRun) {
  const FourRegions s;
  PropagationOptions o;
  std::atomic<int> calls{0};
  o.progress = [&calls](const PropagationProgress&) {
    ++calls;
    return false;
  };
  EXPECT_THROW(regionConnectivity(s.domain, s.metric, s.regions, o, 2), Cancelled);
  EXPECT_LE(calls.load(), 2);  // one report per propagation started, on at most two threads
}

}  // namespace
}  // namespace stvd
