// Geodesic paths against curves known in closed form: under a constant
// metric the path between two points is the straight segment; under the
// pull-back G = J^T J of a smooth map phi it is the pre-image of the straight
// segment phi(s) -> phi(t). Deviations are measured in voxels (continuous
// index units of the grid, so an anisotropic spacing counts per axis). Also:
// the discrete predecessor path, sources on the image border, masked
// voxels that the path must not cut through, and a target on a ridge of the
// distance field where the gradient vanishes.
//
// Every propagation here runs STVD with k = 8, the largest-norm chain
// measure and 26 neighbours: the configuration the bounds below were
// measured on. On the library's default field (segment measure, k = 6) the
// refined paths keep the requirement of 1 voxel but not all of these
// tighter bounds (docs/paths.md, "Accuracy"). Masks, walls and contacts:
// path_region_test.cpp.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <array>
#include <chrono>
#include <cstdio>
#include <limits>
#include <vector>

#include "exact_metrics.hpp"
#include "method_cases.hpp"
#include "scenes.hpp"
#include "stvd/voxel_grid/path_tracing.hpp"
#include "stvd/voxel_grid/path_refinement.hpp"
#include "stvd/propagation/propagation.hpp"
#include "stvd/voxel_grid/voxel_grid_propagation.hpp"

namespace stvd {
namespace {

PropagationOptions toolDefaults() {
  return test::withMethod(Method::ShortTermVectorDijkstra, 8, ChainMeasure::LargestEdgeNorm);
}

/// Max and mean distance (voxels) of the path's points from a reference
/// curve given by dense samples, both converted to continuous indices.
struct Deviation {
  double max = 0.0, mean = 0.0;
};

Deviation deviationFromCurve(const GridGeometry& g, const std::vector<Vec3d>& path, const std::vector<Vec3d>& curve) {
  std::vector<Vec3d> curveIndex;
  for (const Vec3d& c : curve) curveIndex.push_back(g.physicalPointToIndex(c));
  Deviation d;
  for (const Vec3d& p : path) {
    const Vec3d pi = g.physicalPointToIndex(p);
    double best = INFINITY;
    for (std::size_t n = 0; n + 1 < curveIndex.size(); ++n) {
      // Distance to the chord between consecutive samples.
      const Vec3d a = curveIndex[n], ab = curveIndex[n + 1] - a;
      const double len2 = dot(ab, ab);
      const double t = len2 > 0.0 ? std::clamp(dot(pi - a, ab) / len2, 0.0, 1.0) : 0.0;
      best = std::min(best, norm(pi - (a + t * ab)));
    }
    d.max = std::max(d.max, best);
    d.mean += best / static_cast<double>(path.size());
  }
  return d;
}

std::vector<Vec3d> segment(Vec3d a, Vec3d b) { return {a, b}; }

// ---------------------------------------------------------------------------

TEST(PredecessorPath, RunsFromASourceToTheTargetThroughNeighboursOfIncreasingDistance) {
  const VoxelGridDomain domain(test::obliqueGrid({20, 16, 12}), Stencil::full26());
  const RiemannianMetric metric = RiemannianMetric::constant(
      domain.vertexCount(), test::toSymTensor(test::uniaxialTensor(4.0, {1.0, 0.5, -0.2})));
  const VertexId source = domain.vertexAt(3, 4, 5), target = domain.vertexAt(17, 12, 2);
  const PropagationResult result = propagate(domain, metric, {source}, toolDefaults());
  const std::vector<VertexId> path = predecessorPath(result, target);
  ASSERT_GE(path.size(), 2u);
  EXPECT_EQ(path.front(), source);
  EXPECT_EQ(path.back(), target);
  for (std::size_t n = 1; n < path.size(); ++n) {
    EXPECT_LT(result.distance[path[n - 1]], result.distance[path[n]]);
    const VoxelIndex a = domain.indexOf(path[n - 1]), b = domain.indexOf(path[n]);
    EXPECT_LE(std::max({std::abs(a.i - b.i), std::abs(a.j - b.j), std::abs(a.k - b.k)}), 1);
  }
  EXPECT_EQ(predecessorPath(result, source), std::vector<VertexId>{source});
}

TEST(PredecessorPath, IsEmptyForATargetThatWasNotReached) {
  std::vector<std::uint8_t> mask(10 * 10 * 10, 1);
  for (int j = 0; j < 10; ++j)
    for (int k = 0; k < 10; ++k) mask[5 + 10 * (j + 10 * k)] = 0;  // a closed wall at i = 5
  GridGeometry g;
  g.size = {10, 10, 10};
  const VoxelGridDomain domain(g, Stencil::full26(), mask);
  const RiemannianMetric metric = RiemannianMetric::constant(domain.vertexCount(), {1, 0, 0, 1, 0, 1});
  const PropagationResult result = propagate(domain, metric, {domain.vertexAt(1, 5, 5)}, toolDefaults());
  EXPECT_TRUE(predecessorPath(result, domain.vertexAt(8, 5, 5)).empty());
  EXPECT_TRUE(traceGeodesicPath(domain, metric, result, domain.vertexAt(8, 5, 5)).points.empty());
}

// ---------------------------------------------------------------------------
// Constant metric: straight segments.

// The traced curve alone (refinement off), measured (Release, x86-64) over
// the paths to the 8 image corners:
//   interior source: max 0.198 voxel, mean 0.081
//   corner source:   max 0.419 voxel, mean 0.099 (paths along the border)
//   5 smoothing passes, one path: max 0.392
// Bound: the requirement, 0.5 voxel (1.2 times the worst).
constexpr double kConstantTracedMaxDeviationVoxels = 0.5;
// Traced curve measured with the metric, relative to the exact distance
// sqrt(d^T G d): measured at most 0.0014.
constexpr double kConstantTracedMetricLengthError = 0.002;
// The refined path (the default): under a constant metric the Gauss-Newton
// matrix is the exact Hessian of the energy, whose minimiser with fixed
// end points is the straight segment, so one step lands on it. Measured
// max 3e-14 voxel (interior source), 1.2e-6 (corner source, paths along
// the border), metric length error at most 1e-7.
constexpr double kConstantMaxDeviationVoxels = 1e-4;
constexpr double kConstantMetricLengthError = 1e-6;

struct StraightPathFigures {
  double worst = 0.0, mean = 0.0, worstLength = 0.0;
};

StraightPathFigures straightPaths(VertexId source, const PathTracingOptions& options) {
  const VoxelGridDomain domain(test::obliqueGrid({40, 32, 24}), Stencil::full26());
  const test::Mat3 g = test::uniaxialTensor(5.0, {1.0, -0.6, 0.4});
  const RiemannianMetric metric = RiemannianMetric::constant(domain.vertexCount(), test::toSymTensor(g));
  const PropagationResult result = propagate(domain, metric, {source}, toolDefaults());
  const int corners[8][3] = {{0, 0, 0},  {39, 0, 0},  {0, 31, 0},  {39, 31, 0},
                             {0, 0, 23}, {39, 0, 23}, {0, 31, 23}, {39, 31, 23}};
  StraightPathFigures f;
  int traced = 0;
  for (const auto& c : corners) {
    const VertexId target = domain.vertexAt(c[0], c[1], c[2]);
    if (target == source) continue;
    const TracedPath path = traceGeodesicPath(domain, metric, result, target, options);
    EXPECT_FALSE(path.points.empty());
    if (path.points.empty()) continue;
    const Vec3d s = domain.physicalPoint(source), t = domain.physicalPoint(target);
    EXPECT_EQ(norm(path.points.front() - s), 0.0) << "the path ends exactly at the source";
    EXPECT_EQ(norm(path.points.back() - t), 0.0) << "the path starts exactly at the target";
    const Deviation d = deviationFromCurve(domain.geometry(), path.points, segment(s, t));
    const double exact = test::tensorNorm(g, t - s);
    f.worst = std::max(f.worst, d.max);
    f.mean += d.mean;
    f.worstLength = std::max(f.worstLength, std::abs(path.metricLength - exact) / exact);
    EXPECT_EQ(path.fallbackCount(), 0u) << "no fallback under a constant metric";
    EXPECT_DOUBLE_EQ(path.geodesicLength, result.distance[target]);
    ++traced;
  }
  f.mean /= std::max(1, traced);
  return f;
}

void expectStraightPaths(VertexId source, const char* label) {
  PathTracingOptions tracedOnly;
  tracedOnly.refine = false;
  const StraightPathFigures before = straightPaths(source, tracedOnly);
  const StraightPathFigures after = straightPaths(source, {});
  std::printf("[ measured ] constant metric, %s source: deviation max %.1e mean %.1e voxel, metric length error "
              "max %.2g; traced only: max %.3f mean %.3f, metric length error %.4f\n",
              label, after.worst, after.mean, after.worstLength, before.worst, before.mean, before.worstLength);
  EXPECT_LE(after.worst, kConstantMaxDeviationVoxels);
  EXPECT_LE(after.worstLength, kConstantMetricLengthError);
  EXPECT_LE(before.worst, kConstantTracedMaxDeviationVoxels);
  EXPECT_LE(before.worstLength, kConstantTracedMetricLengthError);
}

TEST(GeodesicPathConstantMetric, IsTheStraightSegmentFromAnInteriorSource) {
  const VoxelGridDomain domain(test::obliqueGrid({40, 32, 24}), Stencil::full26());
  expectStraightPaths(domain.vertexAt(21, 13, 9), "interior");
}

TEST(GeodesicPathConstantMetric, IsTheStraightSegmentFromASourceInAnImageCorner) {
  // Seeds on the image border: one-sided differences there, and the path
  // still ends exactly on the seed.
  const VoxelGridDomain domain(test::obliqueGrid({40, 32, 24}), Stencil::full26());
  expectStraightPaths(domain.vertexAt(0, 31, 0), "corner");
}

// ---------------------------------------------------------------------------
// Pull-back metric: pre-images of straight segments.

/// The pull-back scene of pullback_metric_accuracy_test.cpp (gamma = 20,
/// shear slopes 0.26): G's anisotropy reaches about 20 and its strong axis
/// swings by up to 15 degrees across the box.
struct PullbackScene {
  VoxelGridDomain domain{test::orientedGrid({48, 40, 32}, {1.0, 1.2, 1.5}, {12.0, -40.5, 3.25},
                                            test::rotation({-0.2, 1.0, 0.6}, 0.45)),
                         Stencil::full26()};
  test::TriangularPullbackMap map;
  RiemannianMetric metric;

  PullbackScene() {
    const GridGeometry& geo = domain.geometry();
    map.r = test::rotation({0.4, 0.3, -1.0}, 0.9);
    map.centre = geo.indexToPhysicalPoint(23.5, 19.5, 15.5);
    map.gamma = 20.0;
    map.a1 = 4.0;
    map.w1 = 2.0 * test::kPi / 96.0;
    map.a3 = 4.0;
    map.w3 = 2.0 * test::kPi / 96.0;
    std::vector<SymTensor3> tensors(domain.vertexCount());
    for (VertexId v = 0; v < domain.vertexCount(); ++v) tensors[v] = test::toSymTensor(map.metric(domain.physicalPoint(v)));
    metric = RiemannianMetric(std::move(tensors));
  }

  /// phi^-1 of the segment phi(s) -> phi(t), densely sampled; empty when it
  /// leaves the box of voxel centres (then the closed form does not apply).
  std::vector<Vec3d> exactGeodesic(Vec3d s, Vec3d t) const {
    const Vec3d a = map(s), b = map(t);
    const int samples = std::max(2, static_cast<int>(std::ceil(norm(b - a) / 0.05)));
    std::vector<Vec3d> curve;
    for (int n = 0; n <= samples; ++n) {
      const Vec3d x = map.inverse(a + (static_cast<double>(n) / samples) * (b - a));
      const Vec3d c = domain.geometry().physicalPointToIndex(x);
      const double ci[3] = {c.x, c.y, c.z};
      for (int axis = 0; axis < 3; ++axis)
        if (ci[axis] < 0.0 || ci[axis] > static_cast<double>(domain.geometry().size[axis] - 1)) return {};
      curve.push_back(x);
    }
    return curve;
  }
};

/// Deviation statistics of the paths from `source` to a lattice of targets
/// (every 6th voxel along each axis) whose closed-form geodesic stays in the
/// grid, traced on the given distance field.
struct PullbackPathStatistics {
  int paths = 0;
  int within1Voxel = 0;
  double worst = 0.0;
  double meanOfMeans = 0.0;
  double secondsPerPath = 0.0;
  double meanIterations = 0.0;
  std::size_t maxIterations = 0;
};

PullbackPathStatistics pullbackPaths(const PullbackScene& scene, const PropagationResult& result, VertexId source,
                                     const PathTracingOptions& options = {}) {
  const VoxelGridDomain& domain = scene.domain;
  PullbackPathStatistics stats;
  for (int i = 1; i < 48; i += 6)
    for (int j = 1; j < 40; j += 6)
      for (int k = 1; k < 32; k += 6) {
        const VertexId target = domain.vertexAt(i, j, k);
        const Vec3d s = domain.physicalPoint(source), t = domain.physicalPoint(target);
        const std::vector<Vec3d> exact = scene.exactGeodesic(s, t);
        if (exact.empty()) continue;
        const auto started = std::chrono::steady_clock::now();
        const TracedPath path = traceGeodesicPath(domain, scene.metric, result, target, options);
        stats.secondsPerPath += std::chrono::duration<double>(std::chrono::steady_clock::now() - started).count();
        stats.meanIterations += path.refinement.iterations;
        stats.maxIterations = std::max(stats.maxIterations, path.refinement.iterations);
        EXPECT_FALSE(path.points.empty());
        if (path.points.empty()) continue;
        EXPECT_EQ(norm(path.points.front() - s), 0.0);
        const Deviation d = deviationFromCurve(domain.geometry(), path.points, exact);
        stats.worst = std::max(stats.worst, d.max);
        stats.meanOfMeans += d.mean;
        stats.within1Voxel += d.max <= 1.0 ? 1 : 0;
        ++stats.paths;
      }
  stats.meanOfMeans /= std::max(1, stats.paths);
  stats.secondsPerPath /= std::max(1, stats.paths);
  stats.meanIterations /= std::max(1, stats.paths);
  return stats;
}

void printPullbackFigures(const char* field, const PullbackPathStatistics& before, const PullbackPathStatistics& after) {
  std::printf("[ measured ] pull-back gamma 20, %s, traced only: deviation max %.3f voxel, mean %.3f voxel, "
              "%d of %d paths within 1 voxel, %.3f ms per path\n", field, before.worst, before.meanOfMeans,
              before.within1Voxel, before.paths, 1e3 * before.secondsPerPath);
  std::printf("[ measured ] pull-back gamma 20, %s, refined: deviation max %.3f voxel, mean %.3f voxel, "
              "%d of %d paths within 1 voxel, %.3f ms per path (tracing included), refinement iterations mean %.1f "
              "max %zu\n", field, after.worst, after.meanOfMeans, after.within1Voxel, after.paths,
              1e3 * after.secondsPerPath, after.meanIterations, after.maxIterations);
}

// The traced curve alone (refinement off) on the closed-form distance
// |phi(x) - phi(s)| sampled at the voxels (with the STVD predecessors for
// fallbacks). Measured (Release, x86-64) over 335 paths: 310 (92.5 %)
// within 1 voxel, max 3.58 voxel, mean 0.28; the worst paths run along G's
// expensive axis (gamma = 20), where the grid resolves the squared
// distance's variation poorly (docs/paths.md). Bounds about 1.3 times the
// measured figures.
constexpr double kPullbackExactFieldTracedMaxVoxels = 4.6;
constexpr double kPullbackExactFieldTracedMeanVoxels = 0.36;
constexpr double kPullbackExactFieldTracedMinFractionWithin1Voxel = 0.85;
// Refined (the default): measured max 0.448 voxel, mean 0.028, all 335
// paths within 1 voxel (the requirement). What is left is the
// discrete geodesic of the trilinearly interpolated metric against the
// smooth one.
constexpr double kPullbackMaxVoxels = 0.55;
constexpr double kPullbackExactFieldMeanVoxels = 0.035;

TEST(GeodesicPathPullbackMetric, TracedOnTheExactDistanceIsThePreImageOfTheStraightSegmentAtGamma20) {
  const PullbackScene scene;
  const VoxelGridDomain& domain = scene.domain;
  const VertexId source = domain.vertexAt(22, 21, 15);
  PropagationResult result = propagate(domain, scene.metric, {source}, toolDefaults());
  const Vec3d image = scene.map(domain.physicalPoint(source));
  for (VertexId v = 0; v < domain.vertexCount(); ++v) result.distance[v] = norm(scene.map(domain.physicalPoint(v)) - image);
  PathTracingOptions tracedOnly;
  tracedOnly.refine = false;
  const PullbackPathStatistics before = pullbackPaths(scene, result, source, tracedOnly);
  const PullbackPathStatistics stats = pullbackPaths(scene, result, source);
  printPullbackFigures("exact field", before, stats);
  EXPECT_GE(stats.paths, 300);
  EXPECT_LE(stats.worst, kPullbackMaxVoxels);
  EXPECT_LE(stats.meanOfMeans, kPullbackExactFieldMeanVoxels);
  EXPECT_EQ(stats.within1Voxel, stats.paths);
  EXPECT_LE(before.worst, kPullbackExactFieldTracedMaxVoxels);
  EXPECT_LE(before.meanOfMeans, kPullbackExactFieldTracedMeanVoxels);
  EXPECT_GE(double(before.within1Voxel) / before.paths, kPullbackExactFieldTracedMinFractionWithin1Voxel);
}

// The same paths on the distance field STVD computes (the tool's defaults),
// which is what `stvd path` does.
//
// The traced curve alone: STVD's distance errors (mean 3 %, max 19 % on
// this scene) tilt the gradient; a geodesic's position is ill-conditioned
// with respect to its length (a lateral offset delta over a length L
// changes the length only by about delta^2 / 2L), so these errors move
// paths by voxels, most along the expensive direction of G
// (docs/paths.md). Measured (Release, x86-64) over 335 paths: 150 (45 %)
// within 1 voxel, max 12.4 voxel, mean 0.94. Bounds about 1.3 times the
// measured figures.
constexpr double kPullbackStvdTracedMaxVoxels = 16.0;
constexpr double kPullbackStvdTracedMeanVoxels = 1.25;
constexpr double kPullbackStvdTracedMinFractionWithin1Voxel = 0.35;
// Refined (the default): the refinement minimises the path's own metric
// energy, so the distance field only chooses where it starts. Measured max
// 0.397 voxel, mean 0.023, all 335 paths within 1 voxel (the issue's
// requirement), as close as the paths from the exact field. The bound
// kPullbackMaxVoxels serves both.
constexpr double kPullbackStvdMeanVoxels = 0.03;

TEST(GeodesicPathPullbackMetric, TracedOnTheStvdDistanceIsThePreImageOfTheStraightSegmentAtGamma20) {
  const PullbackScene scene;
  const VoxelGridDomain& domain = scene.domain;
  const VertexId source = domain.vertexAt(22, 21, 15);
  const PropagationResult result = propagate(domain, scene.metric, {source}, toolDefaults());
  PathTracingOptions tracedOnly;
  tracedOnly.refine = false;
  const PullbackPathStatistics before = pullbackPaths(scene, result, source, tracedOnly);
  const PullbackPathStatistics stats = pullbackPaths(scene, result, source);
  printPullbackFigures("STVD field", before, stats);
  EXPECT_GE(stats.paths, 300);
  EXPECT_LE(stats.worst, kPullbackMaxVoxels);
  EXPECT_LE(stats.meanOfMeans, kPullbackStvdMeanVoxels);
  EXPECT_EQ(stats.within1Voxel, stats.paths);
  EXPECT_LE(before.worst, kPullbackStvdTracedMaxVoxels);
  EXPECT_LE(before.meanOfMeans, kPullbackStvdTracedMeanVoxels);
  EXPECT_GE(double(before.within1Voxel) / before.paths, kPullbackStvdTracedMinFractionWithin1Voxel);
}

// ---------------------------------------------------------------------------
// Failure modes of path tracers.

/// True when p lies strictly inside the box of a voxel outside the domain.
bool insideMaskedVoxel(const VoxelGridDomain& domain, Vec3d p) {
  const Vec3d c = domain.geometry().physicalPointToIndex(p);
  const int i = static_cast<int>(std::lround(c.x)), j = static_cast<int>(std::lround(c.y)),
            k = static_cast<int>(std::lround(c.z));
  if (!domain.isInsideImage(i, j, k)) return true;
  const double margin = 0.5 - 1e-9;
  const bool strictlyInside = std::abs(c.x - i) < margin && std::abs(c.y - j) < margin && std::abs(c.z - k) < margin;
  return strictlyInside && !domain.contains(domain.vertexAt(i, j, k));
}

TEST(GeodesicPathFailureModes, NeverCutsThroughMaskedVoxels) {
  // A wall at i = 15 with a 3 x 3 hole away from the straight line; the
  // straight segment from source to target crosses the wall.
  GridGeometry g;
  g.size = {30, 30, 20};
  g.spacing = {1.0, 1.0, 1.5};
  std::vector<std::uint8_t> mask(g.voxelCount(), 1);
  for (int k = 0; k < 20; ++k)
    for (int j = 0; j < 30; ++j) {
      const bool hole = j >= 21 && j <= 23 && k >= 9 && k <= 11;
      if (!hole) mask[15 + 30 * (j + 30 * k)] = 0;
    }
  const VoxelGridDomain domain(g, Stencil::full26(), mask);
  const RiemannianMetric metric = RiemannianMetric::constant(domain.vertexCount(), {1, 0, 0, 1, 0, 1});
  const VertexId source = domain.vertexAt(4, 8, 10), target = domain.vertexAt(26, 8, 10);
  const PropagationResult result = propagate(domain, metric, {source}, toolDefaults());
  const TracedPath path = traceGeodesicPath(domain, metric, result, target);
  ASSERT_FALSE(path.points.empty());
  EXPECT_EQ(norm(path.points.front() - domain.physicalPoint(source)), 0.0);
  std::size_t masked = 0;
  for (std::size_t n = 1; n < path.points.size(); ++n)
    for (int s = 0; s <= 20; ++s) {
      const Vec3d p = path.points[n - 1] + (s / 20.0) * (path.points[n] - path.points[n - 1]);
      masked += insideMaskedVoxel(domain, p) ? 1 : 0;
    }
  EXPECT_EQ(masked, 0u) << "samples of the path inside masked voxels";
  // Around the wall, not through it: longer than the straight 22 mm.
  EXPECT_GT(path.euclideanLength, 30.0);
  EXPECT_LE(path.euclideanLength, 1.2 * result.distance[target]);
  std::printf("[ measured ] around the wall: length %.4f mm, %zu refinement iterations, %zu moves held\n",
              path.euclideanLength, path.refinement.iterations, path.refinement.heldMoves);
}

TEST(GeodesicPathFailureModes, FallsBackToThePredecessorChainWhereTheGradientVanishes) {
  // Two sources: the target lies on the ridge between them, where the
  // central difference across the ridge is zero and the descent runs along
  // the ridge into the saddle midway between the sources, where the
  // gradient vanishes. The path must not stall there: it reaches a source.
  GridGeometry g;
  g.size = {41, 31, 21};
  const VoxelGridDomain domain(g, Stencil::full26());
  const RiemannianMetric metric = RiemannianMetric::constant(domain.vertexCount(), {1, 0, 0, 1, 0, 1});
  const VertexId a = domain.vertexAt(10, 15, 10), b = domain.vertexAt(30, 15, 10);
  const PropagationResult result = propagate(domain, metric, {a, b}, toolDefaults());
  const VertexId target = domain.vertexAt(20, 15, 10);  // the saddle itself
  const TracedPath path = traceGeodesicPath(domain, metric, result, target);
  ASSERT_FALSE(path.points.empty());
  const Vec3d end = path.points.front();
  EXPECT_TRUE(norm(end - domain.physicalPoint(a)) == 0.0 || norm(end - domain.physicalPoint(b)) == 0.0);
  EXPECT_GE(path.fallbacks[static_cast<int>(PathFallback::GradientVanishes)], 1u);
  EXPECT_LE(path.euclideanLength, 10.0 * 1.1);
}

TEST(GeodesicPathFailureModes, AnExhaustedStepBudgetEndsOnThePredecessorChain) {
  GridGeometry g;
  g.size = {30, 30, 30};
  const VoxelGridDomain domain(g, Stencil::full26());
  const RiemannianMetric metric = RiemannianMetric::constant(domain.vertexCount(), {1, 0, 0, 1, 0, 1});
  const VertexId source = domain.vertexAt(3, 3, 3), target = domain.vertexAt(26, 20, 12);
  const PropagationResult result = propagate(domain, metric, {source}, toolDefaults());
  PathTracingOptions options;
  options.stepBudgetFactor = 0.5;  // half the discrete path's length in steps: not enough
  const TracedPath path = traceGeodesicPath(domain, metric, result, target, options);
  ASSERT_FALSE(path.points.empty());
  EXPECT_EQ(norm(path.points.front() - domain.physicalPoint(source)), 0.0);
  EXPECT_EQ(path.fallbacks[static_cast<int>(PathFallback::StepLimit)], 1u);
  EXPECT_GT(path.discretePoints, 0u);
}

// Paths that run inside a face of the image box, traced on STVD's distance
// (refinement off): measured max 0.84 voxel over the 14 paths below, more
// than the 0.5 voxel of paths through the interior; on the exact distance
// field the same paths stay within 0.5 voxel, so the difference is the
// propagation's (a border voxel has fewer neighbours to take its distance
// from). Bound about 1.3 times the measured figure.
constexpr double kBorderFaceTracedMaxDeviationVoxels = 1.1;
// Refined (the default), the same paths are straight: measured max 1.5e-6
// voxel. The refinement fixes the coordinates on the image box that the
// descent pushes out and lets the points slide along it.
constexpr double kBorderFaceMaxDeviationVoxels = 1e-4;

TEST(GeodesicPathFailureModes, DirectionCosinesFromSinglePrecisionHeadersKeepBorderPathsInTheImage) {
  // NIfTI headers store the direction cosines in single precision: they are
  // orthonormal only to about 1e-7, so a voxel centre on the border maps
  // back to an index a little outside the image. Paths along the border
  // must still be traced (this once ended in an endless fallback loop).
  GridGeometry g = test::obliqueGrid({40, 32, 24});
  for (double& c : g.direction) c = static_cast<float>(c);
  g.origin = {-121.3, 97.6, -40.2};
  const VoxelGridDomain domain(g, Stencil::full26());
  const RiemannianMetric metric = RiemannianMetric::constant(
      domain.vertexCount(), test::toSymTensor(test::uniaxialTensor(5.0, {1.0, -0.6, 0.4})));
  const VertexId source = domain.vertexAt(39, 31, 0);
  const PropagationResult result = propagate(domain, metric, {source}, toolDefaults());
  PathTracingOptions tracedOnly;
  tracedOnly.refine = false;
  double worst = 0.0, worstTraced = 0.0;
  for (int i = 0; i < 40; i += 3) {
    const VertexId target = domain.vertexAt(i, 0, 0);
    const Vec3d s = domain.physicalPoint(source), t = domain.physicalPoint(target);
    for (const bool refine : {false, true}) {
      const TracedPath path = traceGeodesicPath(domain, metric, result, target, refine ? PathTracingOptions{} : tracedOnly);
      ASSERT_FALSE(path.points.empty());
      EXPECT_EQ(norm(path.points.front() - s), 0.0);
      EXPECT_EQ(norm(path.points.back() - t), 0.0);
      const Deviation d = deviationFromCurve(g, path.points, segment(s, t));
      EXPECT_EQ(path.fallbackCount(), 0u) << "target (" << i << ", 0, 0)";
      (refine ? worst : worstTraced) = std::max(refine ? worst : worstTraced, d.max);
      // Every point stays in the image (the box of voxel centres).
      for (const Vec3d& p : path.points) {
        const Vec3d c = g.physicalPointToIndex(p);
        EXPECT_TRUE(c.x >= -1e-3 && c.x <= 39 + 1e-3 && c.y >= -1e-3 && c.y <= 31 + 1e-3 && c.z >= -1e-3 &&
                    c.z <= 23 + 1e-3);
      }
    }
  }
  std::printf("[ measured ] constant metric, paths along the border face: deviation max %.1e voxel "
              "(traced only: %.3f)\n", worst, worstTraced);
  EXPECT_LE(worst, kBorderFaceMaxDeviationVoxels);
  EXPECT_LE(worstTraced, kBorderFaceTracedMaxDeviationVoxels);
}

// Measured: 31.605 mm after 27 iterations, 1.28 mm (4 %) above the
// shortest admissible curve, from 54 mm. The iteration stops short where
// points press against the masked cells: a point whose move or segment
// would enter them slides along their faces or stays, and the steps of the
// others shrink until the energy no longer decreases (docs/paths.md).
constexpr double kDetourExcessMm = 1.5;

TEST(GeodesicPathRefinement, PullsADetourTightAroundMaskedVoxelsWithoutEnteringThem) {
  // A block of masked voxels (i 12..17, j 0..14) between source and target
  // and a wide detour around it. A point may not lie in a cell with a
  // masked corner, so the shortest admissible curve runs from (5, 5) to the
  // cell corner (11, 15), along j = 15 to (18, 15) and down to (25, 5):
  // 2 sqrt(6^2 + 10^2) + 7 = 30.324 mm.
  GridGeometry g;
  g.size = {30, 30, 5};
  std::vector<std::uint8_t> mask(g.voxelCount(), 1);
  for (int k = 0; k < 5; ++k)
    for (int j = 0; j <= 14; ++j)
      for (int i = 12; i <= 17; ++i) mask[i + 30 * (j + 30 * k)] = 0;
  const VoxelGridDomain domain(g, Stencil::full26(), mask);
  const RiemannianMetric metric = RiemannianMetric::constant(domain.vertexCount(), {1, 0, 0, 1, 0, 1});
  const std::vector<double> reached(domain.vertexCount(), 1.0);
  const Vec3d source = g.indexToPhysicalPoint(5, 5, 2), target = g.indexToPhysicalPoint(25, 5, 2);
  std::vector<Vec3d> points = {source, g.indexToPhysicalPoint(5, 22, 2), g.indexToPhysicalPoint(25, 22, 2), target};
  const PathRefinementReport report = refineGeodesicPath(domain, metric, reached, points);
  ASSERT_GE(points.size(), 3u);
  EXPECT_EQ(norm(points.front() - source), 0.0);
  EXPECT_EQ(norm(points.back() - target), 0.0);
  double length = 0.0;
  std::size_t masked = 0;
  for (std::size_t n = 1; n < points.size(); ++n) {
    length += norm(points[n] - points[n - 1]);
    for (int s = 0; s <= 20; ++s)
      masked += insideMaskedVoxel(domain, points[n - 1] + (s / 20.0) * (points[n] - points[n - 1])) ? 1 : 0;
  }
  const double shortest = 2.0 * std::sqrt(36.0 + 100.0) + 7.0;
  std::printf("[ measured ] detour around a masked block: length %.4f mm (shortest admissible %.4f), "
              "%zu iterations, %zu moves held\n", length, shortest, report.iterations, report.heldMoves);
  EXPECT_EQ(masked, 0u) << "samples of the path inside masked voxels";
  EXPECT_GE(length, shortest - 1e-9);
  EXPECT_LE(length, shortest + kDetourExcessMm);
  EXPECT_GT(report.iterations, 0u);
}

TEST(GeodesicPathOptions, SmoothingKeepsTheEndPointsAndStaysNearTheCurve) {
  const VoxelGridDomain domain(test::obliqueGrid({30, 24, 20}), Stencil::full26());
  const test::Mat3 g = test::uniaxialTensor(3.0, {0.2, 1.0, 0.4});
  const RiemannianMetric metric = RiemannianMetric::constant(domain.vertexCount(), test::toSymTensor(g));
  const VertexId source = domain.vertexAt(2, 3, 4), target = domain.vertexAt(27, 20, 15);
  const PropagationResult result = propagate(domain, metric, {source}, toolDefaults());
  PathTracingOptions options;
  options.smoothingPasses = 5;
  for (const bool refine : {false, true}) {
    options.refine = refine;
    const TracedPath path = traceGeodesicPath(domain, metric, result, target, options);
    ASSERT_FALSE(path.points.empty());
    EXPECT_EQ(norm(path.points.front() - domain.physicalPoint(source)), 0.0);
    EXPECT_EQ(norm(path.points.back() - domain.physicalPoint(target)), 0.0);
    const Deviation d = deviationFromCurve(domain.geometry(), path.points,
                                           segment(domain.physicalPoint(source), domain.physicalPoint(target)));
    std::printf("[ measured ] constant metric, 5 smoothing passes, %s: deviation max %.3g voxel\n",
                refine ? "refined" : "traced only", d.max);
    EXPECT_LE(d.max, refine ? kConstantMaxDeviationVoxels : kConstantTracedMaxDeviationVoxels);
  }
}

TEST(GeodesicPathOptions, RejectsOptionsOutOfRange) {
  GridGeometry g;
  g.size = {5, 5, 5};
  const VoxelGridDomain domain(g, Stencil::full26());
  const RiemannianMetric metric = RiemannianMetric::constant(domain.vertexCount(), {1, 0, 0, 1, 0, 1});
  const PropagationResult result = propagate(domain, metric, {0}, toolDefaults());
  PathTracingOptions bad;
  bad.stepFraction = 0.0;
  EXPECT_THROW(traceGeodesicPath(domain, metric, result, 10, bad), std::invalid_argument);
  EXPECT_THROW(traceGeodesicPath(domain, metric, result, 125), std::invalid_argument);
}

TEST(InterpolateAtPoint, IsTrilinearBetweenVoxelCentresAndNanOutside) {
  const VoxelGridDomain domain(test::obliqueGrid({4, 4, 4}), Stencil::full26());
  std::vector<float> values(domain.vertexCount());
  for (VertexId v = 0; v < domain.vertexCount(); ++v) {
    const VoxelIndex c = domain.indexOf(v);
    values[v] = static_cast<float>(1.0 + 2.0 * c.i - 0.5 * c.j + 0.25 * c.k);
  }
  const GridGeometry& g = domain.geometry();
  EXPECT_NEAR(interpolateAtPoint(domain, values, g.indexToPhysicalPoint(1.5, 2.25, 0.75)),
              1.0 + 3.0 - 1.125 + 0.1875, 1e-6);
  EXPECT_NEAR(interpolateAtPoint(domain, values, g.indexToPhysicalPoint(3, 3, 3)), 1.0 + 6.0 - 1.5 + 0.75, 1e-6);
  EXPECT_TRUE(std::isnan(interpolateAtPoint(domain, values, g.indexToPhysicalPoint(3.2, 1, 1))));
}

}  // namespace
}  // namespace stvd

namespace stvd {
namespace {

// A value is sampled only from voxels inside the domain, and only at points
// of the domain's region, where paths run: at a voxel centre next to a masked
// voxel (whose weight is zero, or a rounding error in an oblique geometry)
// and on a grid edge between two domain voxels the value is defined (FA along
// a path that ends at the brain's edge is never NaN); in a cell face or cube
// with a masked corner, which no path crosses, it is NaN.
TEST(InterpolateAtPoint, UsesOnlyVoxelsInsideTheDomain) {
  const GridGeometry g = test::obliqueGrid({4, 4, 4});
  std::vector<std::uint8_t> mask(64, 1);
  const auto at = [](int i, int j, int k) { return static_cast<std::size_t>(i + 4 * (j + 4 * k)); };
  mask[at(2, 1, 1)] = 0;
  const VoxelGridDomain domain(g, Stencil::full26(), mask);
  std::vector<float> values(64, 0.f);
  for (VertexId v = 0; v < 64; ++v) {
    const VoxelIndex c = domain.indexOf(v);
    values[v] = static_cast<float>(1.0 + c.i + 10.0 * c.j + 100.0 * c.k);
  }
  values[at(2, 1, 1)] = std::numeric_limits<float>::quiet_NaN();  // no value outside the domain
  // The voxel centre of a neighbour of the masked voxel, reached through the
  // oblique geometry's rounding, gives its own value.
  EXPECT_NEAR(interpolateAtPoint(domain, values, g.indexToPhysicalPoint(1, 1, 1)), 112.0, 1e-6);
  // A quarter of the way along the grid edge from (1,1,1) to (1,2,1).
  EXPECT_NEAR(interpolateAtPoint(domain, values, g.indexToPhysicalPoint(1, 1.25, 1)), 0.75 * 112.0 + 0.25 * 122.0,
              1e-5);
  // Inside a cube whose eight corners are in the domain: trilinear.
  EXPECT_NEAR(interpolateAtPoint(domain, values, g.indexToPhysicalPoint(1.5, 2.25, 1.75)), 1.0 + 1.5 + 22.5 + 175.0,
              1e-5);
  // Towards the masked voxel, in a face and in a cube that hold it: no value.
  EXPECT_TRUE(std::isnan(interpolateAtPoint(domain, values, g.indexToPhysicalPoint(1.5, 1, 1))));
  EXPECT_TRUE(std::isnan(interpolateAtPoint(domain, values, g.indexToPhysicalPoint(1.5, 1.25, 1))));
  EXPECT_TRUE(std::isnan(interpolateAtPoint(domain, values, g.indexToPhysicalPoint(1.5, 1.25, 1.5))));
}

}  // namespace
}  // namespace stvd
