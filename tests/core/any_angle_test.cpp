// Any-angle ancestors (PropagationOptions::anyAngleAncestors, issue 33):
// besides the k vertices of its chain of edges, a relaxation offers the
// vertex that v's distance was measured from (the start of the straight
// segment that gave it, a source within the source reach) as a candidate
// base, so that the memory reaches a distance rather than k edges. The
// result's predecessor of a vertex is then where its distance was measured
// from, not necessarily a neighbour.
//
// What must hold whatever the candidates: every distance is the length of a
// path in the domain measured along itself, so a vertex's distance is its
// predecessor's plus the length of the segment between them, measured as a
// candidate is measured, and that segment lies in the domain (masks with
// thin walls, a tetrahedral mesh with a notch). What the ancestors buy, on
// a constant metric whose cheap axis no lattice direction follows: an error
// that falls with the resolution and a bounded worst voxel.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>
#include <vector>

#include "exact_metrics.hpp"
#include "kuhn_lattice.hpp"
#include "relative_error.hpp"
#include "scenes.hpp"
#include "stvd/cell_mesh/cell_mesh_candidate_path.hpp"
#include "stvd/cell_mesh/cell_mesh_propagation.hpp"
#include "stvd/propagation/propagation.hpp"
#include "stvd/voxel_grid/voxel_grid_candidate_path.hpp"
#include "stvd/voxel_grid/voxel_grid_propagation.hpp"
#include "wall_scenes.hpp"

namespace stvd {
namespace {

/// G with eigenvalue `cheap` along (1, 2, 3)/sqrt(14), and `middle`,
/// `expensive` along (-2, 1, 0)/sqrt(5) and the third axis: the scenes of the
/// refinement benchmark (docs/benchmarks.md).
test::Mat3 rotatedTensor(double cheap, double middle, double expensive) {
  const Vec3d a = test::normalized({1, 2, 3}), b = test::normalized({-2, 1, 0});
  const Vec3d c{a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x};
  const Vec3d axes[3] = {a, b, c};
  const double lambda[3] = {cheap, middle, expensive};
  test::Mat3 g;
  for (int r = 0; r < 3; ++r)
    for (int s = 0; s < 3; ++s) {
      double sum = 0.0;
      for (int m = 0; m < 3; ++m) {
        const double* e = &axes[m].x;
        sum += lambda[m] * e[r] * e[s];
      }
      g(r, s) = sum;
    }
  return g;
}

/// Mean, 99th percentile and largest relative error over the voxels more
/// than three voxels from the source.
struct Tails {
  double mean = 0.0, p99 = 0.0, max = 0.0;
  std::size_t count = 0;
};

Tails constantMetricTails(int n, const test::Mat3& g, const PropagationOptions& options, const std::string& label) {
  GridGeometry geometry;
  geometry.size = {std::size_t(n), std::size_t(n), std::size_t(n)};
  const VoxelGridDomain domain(geometry, Stencil::full26());
  const RiemannianMetric metric = RiemannianMetric::constant(domain.vertexCount(), test::toSymTensor(g));
  const VertexId source = domain.vertexAt(n / 2, n / 2, n / 2);
  const PropagationResult r = propagate(domain, metric, {source}, options);
  const Vec3d s = domain.physicalPoint(source);
  // The straight line under the tensor the propagation measures with (its
  // single-precision entries), which no path undercuts.
  const SymTensor3 f = test::toSymTensor(g);
  test::Mat3 used;
  used.a = {f.xx, f.xy, f.xz, f.xy, f.yy, f.yz, f.xz, f.yz, f.zz};
  std::vector<double> errors;
  for (VertexId v = 0; v < domain.vertexCount(); ++v) {
    const Vec3d x = domain.physicalPoint(v);
    if (norm(x - s) <= 3.0) continue;
    const double exact = test::tensorNorm(g, x - s);
    EXPECT_GE(r.distance[v], test::tensorNorm(used, x - s) * (1.0 - 1e-5)) << label << ": vertex " << v;
    errors.push_back(std::abs(r.distance[v] - exact) / exact);
  }
  std::sort(errors.begin(), errors.end());
  Tails t;
  for (double e : errors) t.mean += e;
  t.count = errors.size();
  t.mean /= static_cast<double>(t.count);
  t.p99 = errors[(errors.size() - 1) * 99 / 100];
  t.max = errors.back();
  std::printf("[ measured ] %-44s mean %.5f  p99 %.5f  max %.5f  (%zu voxels)\n", label.c_str(), t.mean, t.p99,
              t.max, t.count);
  return t;
}

/// On a grid: every reached vertex's distance is its predecessor's plus the
/// segment between them, measured as the propagation measures a candidate
/// (CandidatePath::segmentLength) or, for a neighbour (the Dijkstra term),
/// as Dijkstra measures the edge (the mean of its end points' tensors), and
/// the segment lies in the domain.
void expectDistancesAreMeasuredSegments(const VoxelGridDomain& domain, const RiemannianMetric& metric,
                                        const PropagationResult& r, const std::string& label) {
  const CandidatePath<VoxelGridDomain, RiemannianNorm> path(domain, metric);
  std::size_t checked = 0, beyondNeighbours = 0;
  for (VertexId v = 0; v < domain.vertexCount(); ++v) {
    const VertexId p = r.predecessor[v];
    if (!std::isfinite(r.distance[v]) || p == kNoVertex) continue;
    ASSERT_TRUE(domain.segmentInDomain(p, v)) << label << ": the segment from " << p << " to " << v
                                              << " leaves the domain";
    double segment = path.segmentLength(p, v);
    bool neighbour = false;
    domain.forEachNeighbor(p, [&](VertexId w, Vec3f) { neighbour = neighbour || w == v; });
    if (neighbour) {
      const Vec3f e = domain.displacement(p, v);
      const double edge =
          RiemannianNorm::length(RiemannianNorm::edgeParams(metric[p], metric[v]), e.x, e.y, e.z);
      if (std::abs(r.distance[p] + edge - r.distance[v]) < std::abs(r.distance[p] + segment - r.distance[v]))
        segment = edge;
    }
    // Equal up to float rounding of the length: the library may evaluate it
    // in a clone with fused multiply-adds, and the quadratic form of an
    // anisotropic tensor loses bits to cancellation (measured up to 7.4e-6
    // of the length here). A wrong base would be off by a good part of a
    // voxel step.
    ASSERT_NEAR(r.distance[v], r.distance[p] + segment, 3e-5 * segment + 1e-9) << label << ": vertex " << v;
    ASSERT_LT(r.distance[p], r.distance[v]) << label << ": vertex " << v;
    beyondNeighbours += path.steps(p, v) > domain.stencil().radius() ? 1 : 0;
    ++checked;
  }
  std::printf("[ measured ] %s: %zu predecessors, %zu of them beyond the stencil\n", label.c_str(), checked,
              beyondNeighbours);
  EXPECT_GT(checked, domain.domainVertexCount() / 2);
  EXPECT_GT(beyondNeighbours, checked / 4) << label << ": the predecessors are the segments' starts";
}

TEST(AnyAngleAncestors, EveryDistanceIsItsPredecessorsPlusTheSegmentFromItMeasuredAlongIt) {
  // A smooth varying metric on an oblique grid with a ball mask, from two
  // sources.
  const GridGeometry g = test::obliqueGrid({36, 36, 36});
  const VoxelGridDomain domain(g, Stencil::full26(), test::ballMask(g, {18, 17, 18}, 16.0));
  const RiemannianMetric metric(test::smoothVaryingTensors(domain), &domain.mask());
  const PropagationResult r =
      propagate(domain, metric, {domain.vertexAt(10, 12, 18), domain.vertexAt(25, 24, 20)}, PropagationOptions{});
  expectDistancesAreMeasuredSegments(domain, metric, r, "oblique ball, varying metric");
}

TEST(AnyAngleAncestors, NoSegmentCrossesAThinWallHoweverFarTheAncestorsReach) {
  // Long reaches, so that ancestors across the wall are within reach of
  // every vertex behind it: every one of them must be refused, and no
  // distance comes out below the path around the wall's end.
  for (const test::WallScene& scene : {test::straightWallWithGap(), test::diagonalWall()}) {
    const VoxelGridDomain domain = scene.slab.domain(Stencil::full26());
    const RiemannianMetric metric = scene.slab.identityMetric();
    PropagationOptions o;
    o.segmentReach = 64;
    o.sourceReach = 64;
    const auto& s = scene.source;
    const auto& t = scene.target;
    const PropagationResult r = propagate(domain, metric, {domain.vertexAt(s[0], s[1], s[2])}, o);
    expectDistancesAreMeasuredSegments(domain, metric, r, scene.name);
    const double exact = scene.exact(VoxelConnectivity::Faces);
    const double d = r.distance[domain.vertexAt(t[0], t[1], t[2])];
    std::printf("[ measured ] %s: %.4f against the path around the wall %.4f\n", scene.name, d, exact);
    EXPECT_GE(d, exact * (1.0 - 1e-6)) << scene.name;
    EXPECT_LE(d, exact * 1.02) << scene.name;
    EXPECT_GT(r.refusedCandidates, 0u) << scene.name;
  }
}

TEST(AnyAngleAncestors, OnATetrahedralMeshEveryDistanceIsItsPredecessorsPlusTheSegmentWalkedThroughIt) {
  // The L-shaped prism of Kuhn tetrahedra: a segment across the missing
  // quadrant leaves the mesh, and the walk refuses it (kRefusedCandidate).
  const test::LShapedPrism prism{8, 4};
  const CellMeshDomain mesh = CellMeshDomain::fromTetrahedra(prism.box.points, prism.tets);
  const RiemannianMetric metric =
      RiemannianMetric::constant(mesh.vertexCount(), SymTensor3{1.f, 0.f, 0.f, 4.f, 0.f, 2.25f});
  const VertexId source = prism.box.id(15, 4, 1);
  const PropagationResult r = propagate(mesh, metric, {source}, PropagationOptions{});
  const CandidatePath<CellMeshDomain, RiemannianNorm> path(mesh, metric);
  std::size_t beyondNeighbours = 0, checked = 0;
  for (VertexId v = 0; v < mesh.vertexCount(); ++v) {
    const VertexId p = r.predecessor[v];
    if (p == kNoVertex) continue;
    const float segment = path.segmentLength(p, v);
    ASSERT_NE(segment, kRefusedCandidate) << "the segment from " << p << " to " << v << " leaves the mesh";
    ASSERT_NEAR(r.distance[v], r.distance[p] + segment, 3e-5 * segment + 1e-9) << "vertex " << v;
    ASSERT_GE(r.distance[v], prism.distance(mesh.physicalPoint(source), mesh.physicalPoint(v), 1.0, 2.0, 1.5) *
                                 (1.0 - 1e-5))
        << "vertex " << v << " is closer than every path to it";
    bool adjacent = false;
    mesh.forEachNeighbor(v, [&](VertexId w, Vec3f) { adjacent = adjacent || w == p; });
    beyondNeighbours += adjacent ? 0 : 1;
    ++checked;
  }
  std::printf("[ measured ] L-shaped mesh: %zu predecessors, %zu of them not neighbours\n", checked, beyondNeighbours);
  EXPECT_GT(beyondNeighbours, checked / 4);
}

// Measured (Release, x86-64), mean / p99 / max over the voxels more than 3
// voxels from the source, eigenvalues (1, 25, 625):
//   the chain alone (anyAngleAncestors = 0), n = 16, 24, 32:
//     0.0021 / 0.039 / 0.13, 0.0028 / 0.051 / 0.16, 0.0032 / 0.059 / 0.18:
//     the error grows with the resolution (n = 48: 0.0036 / 0.066 / 0.20);
//   with the ancestors, reaches n / 4 (the defaults grow like that from
//   128^3 on, anyAngleReach): 0.0021 / 0.036 / 0.13, 0.0018 / 0.032 / 0.13,
//   0.0015 / 0.026 / 0.15.
TEST(AnyAngleAncestors, ConstantMetricErrorFallsUnderRefinementWhereTheChainAloneGrows) {
  const test::Mat3 g = rotatedTensor(1.0, 25.0, 625.0);
  double previous = 1.0, previousChain = 0.0;
  for (int n : {16, 24, 32}) {
    PropagationOptions o;
    o.segmentReach = n / 4;
    o.sourceReach = n / 4;
    const Tails t = constantMetricTails(n, g, o, "(1, 25, 625) n = " + std::to_string(n) + ", ancestors");
    PropagationOptions chain;
    chain.anyAngleAncestors = 0;
    const Tails c = constantMetricTails(n, g, chain, "(1, 25, 625) n = " + std::to_string(n) + ", chain alone");
    EXPECT_LT(t.mean, previous) << "n = " << n;
    EXPECT_GT(c.mean, previousChain) << "n = " << n;
    if (n > 16) {
      EXPECT_LT(t.mean, 0.7 * c.mean) << "n = " << n;
    }
    previous = t.mean;
    previousChain = c.mean;
  }
}

// Measured at 32^3, mean / p99 / max, eigenvalues (1, 25, 25), then
// (1, 25, 625):
//   defaults (source reach 16: the whole grid):  0 / 0 / 0 and
//     0 / 0 / 0.0097 (one voxel at the grid's corner);
//   the ancestors without source factoring (source reach 6, as any other
//     ancestor's): 0.0016 / 0.022 / 0.081, 0.0022 / 0.038 / 0.147;
//   the chain alone: 0.0024 / 0.035 / 0.120, 0.0032 / 0.059 / 0.182.
TEST(AnyAngleAncestors, OnAConstantRotatedMetricTheDefaultsAreExactAndTheAncestorsAloneCutTheError) {
  for (const auto& [middle, expensive] : {std::pair{25.0, 25.0}, std::pair{25.0, 625.0}}) {
    const test::Mat3 g = rotatedTensor(1.0, middle, expensive);
    const std::string name = "(1, 25, " + std::to_string(int(expensive)) + ") n = 32";
    const Tails d = constantMetricTails(32, g, PropagationOptions{}, name + ", defaults");
    EXPECT_LT(d.mean, 1e-5) << name;
    EXPECT_LT(d.max, 0.05) << name;
    PropagationOptions ancestors;
    ancestors.sourceReach = 6;
    const Tails t = constantMetricTails(32, g, ancestors, name + ", ancestors, source reach 6");
    PropagationOptions chain;
    chain.anyAngleAncestors = 0;
    const Tails c = constantMetricTails(32, g, chain, name + ", chain alone");
    EXPECT_LT(t.mean, 0.75 * c.mean) << name;
    EXPECT_LT(t.p99, 0.75 * c.p99) << name;
    EXPECT_LT(t.max, c.max) << name;
  }
}

TEST(AnyAngleAncestors, SourceFactoringMakesAConstantMetricExactWithinTheSourceReach) {
  // Every voxel of a 24^3 grid lies within 12 voxel steps of the centre:
  // the straight segment from the source is a candidate of every vertex
  // whose own segment starts there, and with a constant norm it wins.
  const test::Mat3 g = rotatedTensor(1.0, 25.0, 625.0);
  PropagationOptions o;
  o.sourceReach = 13;
  const Tails t = constantMetricTails(24, g, o, "(1, 25, 625) n = 24, source reach 13");
  // Up to the float rounding of a segment of up to 12 samples (measured
  // 1.4e-5).
  EXPECT_LT(t.max, 1e-4);
}

TEST(AnyAngleAncestors, NoAncestorIsACandidatePastAChangeOfTheMetric) {
  // Two constant halves, the right one's tensor 1.5 times the left one's
  // (parameters 50 % apart, beyond the propagation's tolerance of 10 %): a
  // vertex in the right half farther than the chain of edges reaches from
  // the change takes its distance from its chain (at most k steps back),
  // the Dijkstra term or an ancestor within the right half, never from a
  // segment that starts across the change, however far the ancestors
  // reach. (Without the rule, 1,637 of the 10,400 vertices checked were
  // measured from the left half.) The source lies farther than the segment
  // reach from every vertex checked: a source within that reach stays a
  // candidate whatever its metric.
  const int interface = 30;
  GridGeometry geometry;
  geometry.size = {64, 20, 20};
  const VoxelGridDomain domain(geometry, Stencil::full26());
  const test::Mat3 g = rotatedTensor(1.0, 4.0, 9.0);
  const SymTensor3 left = test::toSymTensor(g);
  const SymTensor3 right{1.5f * left.xx, 1.5f * left.xy, 1.5f * left.xz,
                         1.5f * left.yy, 1.5f * left.yz, 1.5f * left.zz};
  std::vector<SymTensor3> tensors(domain.vertexCount());
  for (VertexId v = 0; v < domain.vertexCount(); ++v) tensors[v] = domain.indexOf(v).i < interface ? left : right;
  const RiemannianMetric metric(std::move(tensors));
  PropagationOptions o;
  o.segmentReach = 20;
  const int k = memoryDepth<VoxelGridDomain>(o);
  const VertexId source = domain.vertexAt(4, 10, 10);
  const PropagationResult r = propagate(domain, metric, {source}, o);
  expectDistancesAreMeasuredSegments(domain, metric, r, "two halves");
  std::size_t checked = 0, acrossTheChange = 0, beyondTheChain = 0;
  for (VertexId v = 0; v < domain.vertexCount(); ++v) {
    const VoxelIndex c = domain.indexOf(v);
    if (c.i < interface + k + 2) continue;
    ASSERT_GT(c.i - 4, *o.segmentReach);
    ++checked;
    const VoxelIndex p = domain.indexOf(r.predecessor[v]);
    acrossTheChange += p.i < interface ? 1 : 0;
    beyondTheChain += std::max({std::abs(p.i - c.i), std::abs(p.j - c.j), std::abs(p.k - c.k)}) > k ? 1 : 0;
  }
  std::printf("[ measured ] two halves: %zu vertices past the chain's reach from the change, %zu measured from "
              "across it, %zu from farther than the chain\n",
              checked, acrossTheChange, beyondTheChain);
  EXPECT_EQ(acrossTheChange, 0u);
  // The ancestors still work within the right half.
  EXPECT_GT(beyondTheChain, checked / 10);
}

TEST(AnyAngleAncestors, OptionsOutsideTheirRangeAreRefused) {
  GridGeometry geometry;
  geometry.size = {8, 8, 8};
  const VoxelGridDomain domain(geometry, Stencil::full26());
  const RiemannianMetric metric =
      RiemannianMetric::constant(domain.vertexCount(), SymTensor3{1.f, 0.f, 0.f, 1.f, 0.f, 1.f});
  auto refused = [&](auto&& change) {
    PropagationOptions o;
    change(o);
    EXPECT_THROW(propagate(domain, metric, {0}, o), std::invalid_argument);
  };
  refused([](PropagationOptions& o) { o.anyAngleAncestors = -1; });
  refused([](PropagationOptions& o) { o.anyAngleAncestors = kMaxAnyAngleAncestors + 1; });
  refused([](PropagationOptions& o) { o.segmentReach = 0; });
  refused([](PropagationOptions& o) { o.sourceReach = 0; });
}

TEST(AnyAngleAncestors, DefaultReachesGrowWithTheResolution) {
  EXPECT_EQ(anyAngleReach(32 * 32 * 32, false), 6);
  EXPECT_EQ(anyAngleReach(32 * 32 * 32, true), 16);
  EXPECT_EQ(anyAngleReach(64 * 64 * 64, true), 32);
  EXPECT_EQ(anyAngleReach(128 * 128 * 128, false), 6);
  EXPECT_EQ(anyAngleReach(128 * 128 * 128, true), 64);
  EXPECT_EQ(anyAngleReach(256 * 256 * 256, false), 13);
  EXPECT_EQ(anyAngleReach(std::uint64_t{1024} * 1024 * 1024, false), 32);
  EXPECT_EQ(anyAngleReach(std::uint64_t{1024} * 1024 * 1024, true), 64);
}

}  // namespace
}  // namespace stvd
