// Lanthier's Steiner-point method on polygon surfaces (docs/steiner.md):
// every face is a cell with M points on each edge, joined pairwise through
// the face and measured with the face's mean tensor. Specifications against
// the closed forms of surface_accuracy_test.cpp's scenes: it converges as M
// grows, never undershoots a constant metric on a plane, and on the curved
// metric it overtakes STVD as M grows.
//
// Figures quoted are measured (Release, x86-64); tolerances are named
// constants about 1.3 times those figures.
#include <gtest/gtest.h>

#include <cmath>
#include <functional>
#include <stdexcept>
#include <string>
#include <vector>

#include "../core/interrupt_recorder.hpp"
#include "../core/relative_error.hpp"
#include "stvd/propagation/propagation.hpp"
#include "stvd/lanthier/lanthier_propagation.hpp"
#include "stvd/surface/surface_domain.hpp"
#include "stvd/surface/surface_metrics.hpp"
#include "stvd/surface/surface_propagation.hpp"
#include "stvd/surface/surface_lanthier.hpp"
#include "surface_meshes.hpp"

namespace stvd::test {
namespace {

using ExactDistance = std::function<double(VertexId)>;

/// Errors at the vertices whose exact distance exceeds `beyond`.
RelativeErrors errorsOf(const std::vector<double>& distance, const SurfaceDomain& surface,
                        const ExactDistance& exact, double beyond = 1e-9) {
  RelativeErrors e;
  for (VertexId v = 0; v < surface.vertexCount(); ++v) {
    const double x = exact(v);
    if (x > beyond) e.add(distance[v], x);
  }
  return e;
}

RelativeErrors steinerErrors(const std::string& label, const SurfaceDomain& surface,
                             const RiemannianMetric& metric, VertexId source, int m,
                             const ExactDistance& exact) {
  LanthierOptions o;
  o.steinerPoints = m;
  const LanthierResult r = lanthierPropagate(surface, metric, {source}, o);
  const RelativeErrors e = errorsOf(r.distance, surface, exact);
  reportMeasurement(label + ", Steiner M=" + std::to_string(m), e);
  return e;
}

RelativeErrors stvdErrors(const std::string& label, const SurfaceDomain& surface,
                          const RiemannianMetric& metric, VertexId source, int k, ChainMeasure measure,
                          const ExactDistance& exact) {
  PropagationOptions o;
  o.method = Method::ShortTermVectorDijkstra;
  o.k = k;
  o.chainMeasure = measure;
  const PropagationResult r = propagate(surface, metric, {source}, o);
  const RelativeErrors e = errorsOf(r.distance, surface, exact);
  reportMeasurement(label + ", STVD k=" + std::to_string(k) +
                        (measure == ChainMeasure::LargestEdgeNorm ? " largest" : " projection"),
                    e);
  return e;
}

/// Errors for M = 1, 2, 4, 8, each checked to be smaller than the one before.
std::vector<RelativeErrors> expectMonotoneConvergence(const std::string& label, const SurfaceDomain& surface,
                                                      const RiemannianMetric& metric, VertexId source,
                                                      const ExactDistance& exact) {
  std::vector<RelativeErrors> errors;
  for (const int m : {1, 2, 4, 8}) {
    errors.push_back(steinerErrors(label, surface, metric, source, m, exact));
    EXPECT_EQ(errors.back().unreached(), 0u) << "M = " << m;
    if (errors.size() > 1) {
      EXPECT_LT(errors.back().mean(), errors[errors.size() - 2].mean()) << "M = " << m;
    }
  }
  return errors;
}

/// Constant metric, anisotropy 6, on the badly shaped tilted plane: every
/// segment is measured exactly, so a Steiner distance is the length of a
/// polyline in the plane and can never be shorter than the straight line;
/// the error is the lattice's, and it shrinks as M grows.
TEST(SurfaceSteiner, OnAPlaneWithAConstantAnisotropicMetricTheErrorShrinksWithMAndNeverUndershoots) {
  const GeneratedSurface s = badlyShapedTiltedPlane();
  const SurfaceDomain surface(s.points, s.faces);
  const auto g = tensor2(6.0, 0.5);
  const RiemannianMetric metric = surfaceMetricFromWorldTensors(
      surface, std::vector<SymTensor3>(surface.vertexCount(), tiltedPlaneWorldTensor(g)));
  const VertexId source = nearestFlatVertex(s, 5.0, 5.0);
  auto exact = [&](VertexId v) {
    return norm2(g, s.flat[v][0] - s.flat[source][0], s.flat[v][1] - s.flat[source][1]);
  };
  const auto e = expectMonotoneConvergence("bad plane, gamma 6", surface, metric, source, exact);
  // Measured mean (max): M=1 0.0823 (0.926), M=2 0.0554 (0.581), M=4 0.0277
  // (0.390), M=8 0.0112 (0.192); M=16 gives 0.00357 (0.053). STVD on the
  // same scene: k=5 0.0125, k=8 0.0073 (surface_accuracy_test.cpp). The
  // needles of this mesh (narrow columns 0.15 of the wide ones) put
  // consecutive edge crossings close together, where snapping a crossing to
  // the nearest of M points costs most.
  constexpr double kMeanToleranceM8 = 0.0145;
  constexpr double kMaxToleranceM8 = 0.25;
  EXPECT_LT(e[3].mean(), kMeanToleranceM8);
  EXPECT_LT(e[3].max(), kMaxToleranceM8);
  // Single-precision segment lengths: at most rounding below the exact value.
  for (const RelativeErrors& x : e) EXPECT_GT(x.minSigned(), -1e-5);
}

/// The curved height field z = 0.5 sin(x) cos(y) under the pull-back of the
/// plane's diag(1, 16) (exact distance sqrt(dx^2 + 16 dy^2)): the faces'
/// mean tensors differ from face to face. STVD is very accurate on this
/// surface: over all vertices M = 8 beats STVD k = 8 with the largest-norm
/// chain measure (the tool's default on images), and M = 16 also beats the
/// projection rule at k = 5 (the library's default) and k = 8 (the tool's
/// default on surfaces), which M = 8 does not; away from the seed M = 8
/// beats them all.
TEST(SurfaceSteiner, OnACurvedHeightFieldTheErrorShrinksWithMAndOvertakesStvd) {
  const GeneratedSurface s = sineHeightField();
  const SurfaceDomain surface(s.points, s.faces);
  const RiemannianMetric metric = surfaceMetricFromWorldTensors(
      surface, std::vector<SymTensor3>(surface.vertexCount(), SymTensor3{1, 0, 0, 16, 0, 0}));
  const VertexId source = nearestFlatVertex(s, kPi, kPi);
  auto exact = [&](VertexId v) {
    return std::hypot(s.flat[v][0] - s.flat[source][0], 4.0 * (s.flat[v][1] - s.flat[source][1]));
  };
  const std::string label = "height field, projected gamma 4";
  const auto e = expectMonotoneConvergence(label, surface, metric, source, exact);
  const auto k5 = stvdErrors(label, surface, metric, source, 5, ChainMeasure::ProjectionWeighted, exact);
  const auto k8 = stvdErrors(label, surface, metric, source, 8, ChainMeasure::ProjectionWeighted, exact);
  const auto k8Largest = stvdErrors(label, surface, metric, source, 8, ChainMeasure::LargestEdgeNorm, exact);
  const auto m16 = steinerErrors(label, surface, metric, source, 16, exact);
  // Measured mean (max): M=1 0.0470 (0.726), M=2 0.0275 (0.401), M=4 0.0148
  // (0.165), M=8 0.00620 (0.0775), M=16 0.00256 (0.0301); STVD k=5
  // projection 0.00484 (0.0716), k=8 projection 0.00364 (0.0507), k=8
  // largest 0.00907 (0.0654). The most negative signed error, -0.0025, is
  // that of measuring each face with its corners' mean tensor: the world
  // tensors are projected into the vertices' tangent planes, not the face's
  // (with the unprojected diag(1, 16, 1e-6) at every vertex, which each face
  // restricts exactly, M=8 gives mean 0.00566 and no error below -6e-7).
  EXPECT_LT(e[3].mean(), k8Largest.mean());
  EXPECT_LT(m16.mean(), e[3].mean());
  EXPECT_LT(m16.mean(), k5.mean());
  EXPECT_LT(m16.mean(), k8.mean());
  EXPECT_EQ(m16.unreached(), 0u);

  // The mean is dominated by the vertices within a few faces of the seed,
  // where one snap to a Steiner point is a large part of a short distance
  // (M=8: mean 0.0207 below distance 2, against STVD k=5's 0.0107). Away
  // from the seed, beyond distance 6 (1334 of the 2400 vertices, 12 and
  // more rings of the y edges), M = 8 is two to three times as accurate as
  // STVD: measured mean (max) M=8 0.00106 (0.0067), STVD k=5 0.00198
  // (0.0130), k=8 0.00326 (0.0097).
  constexpr double kFarField = 6.0;
  LanthierOptions o;
  o.steinerPoints = 8;
  const RelativeErrors farSteiner =
      errorsOf(lanthierPropagate(surface, metric, {source}, o).distance, surface, exact, kFarField);
  PropagationOptions p;
  p.chainMeasure = ChainMeasure::ProjectionWeighted;  // the figures quoted are the paper's rule's
  p.k = 5;
  const RelativeErrors farK5 = errorsOf(propagate(surface, metric, {source}, p).distance, surface, exact, kFarField);
  p.k = 8;
  const RelativeErrors farK8 = errorsOf(propagate(surface, metric, {source}, p).distance, surface, exact, kFarField);
  reportMeasurement(label + ", beyond 6, Steiner M=8", farSteiner);
  reportMeasurement(label + ", beyond 6, STVD k=5 projection", farK5);
  reportMeasurement(label + ", beyond 6, STVD k=8 projection", farK8);
  constexpr double kFarMeanToleranceM8 = 0.0014;
  EXPECT_LT(farSteiner.mean(), kFarMeanToleranceM8);
  EXPECT_LT(farSteiner.mean(), farK5.mean());
  EXPECT_LT(farSteiner.mean(), farK8.mean());
  constexpr double kMeanToleranceM8 = 0.0081;
  constexpr double kMeanToleranceM16 = 0.0034;
  EXPECT_LT(e[3].mean(), kMeanToleranceM8);
  EXPECT_LT(m16.mean(), kMeanToleranceM16);
}

/// Polygons are cells as they are: on the jittered quad plane (no
/// triangulation) the Steiner distances converge to the planar distance.
TEST(SurfaceSteiner, QuadFacesAreCellsWithoutTriangulation) {
  const GeneratedSurface s = badlyShapedTiltedPlane(true);
  const SurfaceDomain surface(s.points, s.faces);
  const RiemannianMetric metric = isotropicSurfaceMetric(surface);
  const VertexId source = nearestFlatVertex(s, 5.0, 5.0);
  auto exact = [&](VertexId v) {
    return std::hypot(s.flat[v][0] - s.flat[source][0], s.flat[v][1] - s.flat[source][1]);
  };
  const auto e = expectMonotoneConvergence("quad plane, gamma 1", surface, metric, source, exact);
  // Measured mean (max): M=1 0.0205 (0.116), M=2 0.00922 (0.0323), M=4
  // 0.00318 (0.0157), M=8 0.00106 (0.00458); STVD k=8 0.00175.
  constexpr double kMeanToleranceM8 = 0.0014;
  EXPECT_LT(e[3].mean(), kMeanToleranceM8);
  for (const RelativeErrors& x : e) EXPECT_GT(x.minSigned(), -1e-5);
}

/// Inside one face every boundary point is reached by its straight segment:
/// with keepPointDistances each Steiner point of a single quad carries the
/// exact tensor norm of its offset from the seed corner, and
/// steinerPointPosition places it m / (M + 1) along its edge from the
/// smaller vertex index to the larger.
TEST(SurfaceSteiner, InsideOneFaceEveryPointGetsTheNormOfItsStraightSegment) {
  const std::vector<Vec3d> points{{0, 0, 0}, {2, 0, 0}, {2, 1, 0}, {0, 1, 0}};
  PolygonList faces;
  faces.add({2, 3, 0, 1});
  const SurfaceDomain surface(points, faces);
  const SymTensor3 g{4, 1, 0, 2, 0, 3};
  const RiemannianMetric metric = surfaceMetricFromWorldTensors(surface, std::vector<SymTensor3>(4, g));
  LanthierOptions o;
  o.steinerPoints = 3;
  o.keepPointDistances = true;
  const LanthierResult r = lanthierPropagate(surface, metric, {0}, o);
  ASSERT_EQ(r.graphPoints, 4u + 4u * 3u);
  ASSERT_EQ(r.pointDistance.size(), r.graphPoints);
  for (SteinerPointId p = 0; p < r.graphPoints; ++p) {
    const Vec3d x = steinerPointPosition(surface, 3, p);
    const double exact = std::sqrt(4 * x.x * x.x + 2 * x.x * x.y + 2 * x.y * x.y);
    EXPECT_NEAR(r.pointDistance[p], exact, 1e-5 * (1 + exact)) << "point " << p;
  }
  // Edges sorted (0,1), (0,3), (1,2), (2,3): point 4 + 3 * 3 + 0 is the
  // first of edge (2, 3), a quarter of the way from vertex 2 to vertex 3.
  const Vec3d q = steinerPointPosition(surface, 3, 4 + 3 * 3);
  EXPECT_NEAR(q.x, 1.5, 1e-12);
  EXPECT_NEAR(q.y, 1.0, 1e-12);
  EXPECT_THROW(steinerPointPosition(surface, 3, 16), std::invalid_argument);
}

TEST(SurfaceSteiner, AComponentWithoutASeedStaysUnreached) {
  const std::vector<Vec3d> points{{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {5, 0, 0}, {6, 0, 0}, {5, 1, 0}};
  PolygonList faces;
  faces.add({0, 1, 2});
  faces.add({3, 4, 5});
  const SurfaceDomain surface(points, faces);
  const RiemannianMetric metric = isotropicSurfaceMetric(surface);
  const LanthierResult r = lanthierPropagate(surface, metric, {0}, {});
  EXPECT_NEAR(r.distance[1], 1.0, 1e-6);
  EXPECT_NEAR(r.distance[2], 1.0, 1e-6);
  for (VertexId v = 3; v < 6; ++v) EXPECT_EQ(r.distance[v], kUnreachable) << "vertex " << v;
  EXPECT_EQ(r.finalizedVertices, 3u);
}

TEST(SurfaceSteiner, RefusesBadInputWithAnException) {
  const std::vector<Vec3d> points{{0, 0, 0}, {1, 0, 0}, {0, 1, 0}};
  PolygonList faces;
  faces.add({0, 1, 2});
  const SurfaceDomain surface(points, faces);
  const RiemannianMetric metric = isotropicSurfaceMetric(surface);
  LanthierOptions o;
  o.steinerPoints = 0;
  EXPECT_THROW(lanthierPropagate(surface, metric, {0}, o), std::invalid_argument);
  o.steinerPoints = kMaxSteinerPoints + 1;
  EXPECT_THROW(lanthierPropagate(surface, metric, {0}, o), std::invalid_argument);
  EXPECT_THROW(lanthierPropagate(surface, metric, {3}, {}), std::invalid_argument);
  EXPECT_THROW(lanthierPropagate(surface, metric, {}, {}), std::invalid_argument);
  const RiemannianMetric tooSmall = RiemannianMetric::constant(2, SymTensor3{1, 0, 0, 1, 0, 1});
  EXPECT_THROW(lanthierPropagate(surface, tooSmall, {0}, {}), std::invalid_argument);
}

// The setup before the propagation (the faces' edges, sides and
// incidences, the propagation's state) is an operation of its own,
// "Steiner cells", with a report at least every 1024 faces or vertices of
// its passes (the interval made zero); stopped at its first report after
// the start, the run is cancelled before any point is final.
TEST(SurfaceSteiner, TheSetupReportsToTheInterrupterAndCanBeStopped) {
  const GeneratedSurface mesh = planeMesh(60, 50, 6.0, 5.0, 1.5, 0.2, false, 7);
  const SurfaceDomain surface(mesh.points, mesh.faces);
  const RiemannianMetric metric = isotropicSurfaceMetric(surface);
  LanthierOptions o;
  o.steinerPoints = 3;
  o.progressInterval = 0.0;
  testing::InterruptRecorder all;
  o.interrupter = &all;
  const LanthierResult full = lanthierPropagate(surface, metric, {0}, o);
  EXPECT_EQ(full.termination, Termination::Completed);
  ASSERT_EQ(all.operations().size(), 2u);
  EXPECT_EQ(all.operations()[0].name, "Steiner cells");
  EXPECT_EQ(all.operations()[1].name, "Steiner-point propagation");
  // 4 passes over 6,000 triangles and 3 over 3,111 vertices.
  EXPECT_GE(all.operations()[0].percents.size(), (4u * 6000 + 3 * 3111) / 1024);
  for (const testing::InterruptRecorder::Operation& op : all.operations()) testing::expectCompleteReports(op);

  testing::InterruptRecorder stopping;
  stopping.stopAtFirstReportAfterStart("Steiner cells");
  o.interrupter = &stopping;
  const LanthierResult r = lanthierPropagate(surface, metric, {0}, o);
  EXPECT_EQ(r.termination, Termination::Cancelled);
  EXPECT_EQ(r.finalizedVertices, 0u);
  for (double d : r.distance) ASSERT_EQ(d, kUnreachable);
  ASSERT_EQ(stopping.operations().size(), 1u);
  // Stopped after 1024 of about 95,000 steps (the cells, then 2 x 30,441 points).
  EXPECT_EQ(stopping.operations()[0].percents, (std::vector<int>{0, 0}));
  EXPECT_EQ(stopping.reportsAfterStop(), 0u);
}

}  // namespace
}  // namespace stvd::test
