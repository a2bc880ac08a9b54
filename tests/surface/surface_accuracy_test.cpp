// Accuracy of Dijkstra and STVD on surfaces against exact distances: a badly
// shaped plane under a constant anisotropic metric (||x - s||_G), a sphere
// (great circles), prisms (developable: distances of the unrolled strip,
// isotropic and anisotropic), quad meshes, and the curvature and vector-field
// metrics where they reduce to a constant metric of the development.
#include <gtest/gtest.h>

#include <cmath>
#include <functional>
#include <string>

#include "../core/relative_error.hpp"
#include "stvd/propagation/propagation.hpp"
#include "stvd/surface/surface_domain.hpp"
#include "stvd/surface/surface_metrics.hpp"
#include "stvd/surface/surface_propagation.hpp"
#include "surface_meshes.hpp"

namespace stvd::test {
namespace {

struct MethodCase {
  const char* name;
  Method method;
  int k;
};
const MethodCase kDijkstra{"Dijkstra", Method::Dijkstra, 1};
const MethodCase kStvd5{"STVD k=5", Method::ShortTermVectorDijkstra, 5};
const MethodCase kStvd8{"STVD k=8", Method::ShortTermVectorDijkstra, 8};

RelativeErrors measure(const std::string& label, const SurfaceDomain& surface,
                       const RiemannianMetric& metric, VertexId source, const MethodCase& m,
                       const std::function<double(VertexId)>& exact) {
  PropagationOptions o;
  o.method = m.method;
  o.k = m.k;
  // The unfolding measure of the paper's section 6, which these figures
  // were measured with.
  o.chainMeasure = ChainMeasure::ProjectionWeighted;
  const PropagationResult r = propagate(surface, metric, {source}, o);
  RelativeErrors e;
  for (VertexId v = 0; v < surface.vertexCount(); ++v) {
    const double x = exact(v);
    if (x > 1e-9) e.add(r.distance[v], x);
  }
  reportMeasurement(label + ", " + m.name, e);
  return e;
}

/// Tolerances are about 1.4 times the figures measured (Release, x86-64),
/// which each call quotes. Where a figure is given as a range, it moved
/// within that range when the arithmetic of the frames changed at the level
/// of single-precision rounding (edge frames in float or double): near-ties
/// between candidates pick other predecessors, and the chains, and so the
/// largest errors, follow. The tolerance covers the largest figure seen.
void expectWithin(const RelativeErrors& e, double meanTolerance, double maxTolerance) {
  EXPECT_EQ(e.unreached(), 0u);
  EXPECT_LT(e.mean(), meanTolerance);
  EXPECT_LT(e.max(), maxTolerance);
}

GeneratedSurface badPlane(bool quads = false) { return badlyShapedTiltedPlane(quads); }
VertexId nearest(const GeneratedSurface& s, double x, double y) { return nearestFlatVertex(s, x, y); }

/// Constant metric (gamma = 6) given as world tensors on the tilted plane:
/// the distance is ||x - s||_G in the plane's coordinates.
TEST(SurfaceAccuracy, BadlyShapedPlaneWithConstantAnisotropicMetricMatchesTheTensorNorm) {
  const GeneratedSurface s = badPlane();
  const SurfaceDomain surface(s.points, s.faces);
  const auto g = tensor2(6.0, 0.5);
  const RiemannianMetric metric = surfaceMetricFromWorldTensors(
      surface, std::vector<SymTensor3>(surface.vertexCount(), tiltedPlaneWorldTensor(g)));
  const VertexId source = nearest(s, 5.0, 5.0);
  auto exact = [&](VertexId v) {
    return norm2(g, s.flat[v][0] - s.flat[source][0], s.flat[v][1] - s.flat[source][1]);
  };
  const auto d = measure("bad plane, gamma 6", surface, metric, source, kDijkstra, exact);
  const auto k5 = measure("bad plane, gamma 6", surface, metric, source, kStvd5, exact);
  const auto k8 = measure("bad plane, gamma 6", surface, metric, source, kStvd8, exact);
  expectWithin(k5, 0.018, 0.25);    // measured mean 0.0106-0.0125, max 0.180
  expectWithin(k8, 0.0105, 0.18);   // measured mean 0.0056-0.0073, max 0.096-0.129
  EXPECT_LT(k5.mean(), 0.1 * d.mean());  // measured: Dijkstra mean 0.232, max 2.86
}

/// A curved, non-developable surface, the height field z = 0.5 sin(x) cos(y)
/// over a badly shaped triangulation, under the pull-back of the plane's
/// metric diag(1, 16) through the projection (x, y, z) -> (x, y): the world
/// tensor diag(1, 16, 0) restricted to each tangent plane. Straight lines of
/// the plane lift to the surface, so the distance is
/// sqrt(dx^2 + 16 dy^2): exact, with tensors that turn from vertex to vertex
/// in the tangent frames.
TEST(SurfaceAccuracy, HeightFieldWithAProjectedMetricMatchesThePlanarTensorNorm) {
  const GeneratedSurface s = sineHeightField();
  const SurfaceDomain surface(s.points, s.faces);
  const RiemannianMetric metric = surfaceMetricFromWorldTensors(
      surface, std::vector<SymTensor3>(surface.vertexCount(), SymTensor3{1, 0, 0, 16, 0, 0}));
  const VertexId source = nearest(s, kPi, kPi);
  auto exact = [&](VertexId v) {
    return std::hypot(s.flat[v][0] - s.flat[source][0], 4.0 * (s.flat[v][1] - s.flat[source][1]));
  };
  const auto d = measure("height field, projected gamma 4", surface, metric, source, kDijkstra, exact);
  const auto k5 = measure("height field, projected gamma 4", surface, metric, source, kStvd5, exact);
  const auto k8 = measure("height field, projected gamma 4", surface, metric, source, kStvd8, exact);
  expectWithin(k5, 0.0068, 0.10);   // measured mean 0.00484, max 0.0716
  expectWithin(k8, 0.0051, 0.071);  // measured mean 0.00364, max 0.0507
  EXPECT_LT(k5.mean(), 0.1 * d.mean());  // measured: Dijkstra mean 0.106, max 1.02
}

/// The paper's isotropic observation (section 7): on badly shaped elements
/// STVD is clearly more accurate than Dijkstra at gamma = 1.
TEST(SurfaceAccuracy, OnABadlyShapedMeshAtGammaOneStvdIsClearlyMoreAccurateThanDijkstra) {
  const GeneratedSurface s = badPlane();
  const SurfaceDomain surface(s.points, s.faces);
  const RiemannianMetric metric = isotropicSurfaceMetric(surface);
  const VertexId source = nearest(s, 5.0, 5.0);
  auto exact = [&](VertexId v) {
    return std::hypot(s.flat[v][0] - s.flat[source][0], s.flat[v][1] - s.flat[source][1]);
  };
  const auto d = measure("bad plane, gamma 1", surface, metric, source, kDijkstra, exact);
  const auto k5 = measure("bad plane, gamma 1", surface, metric, source, kStvd5, exact);
  const auto k8 = measure("bad plane, gamma 1", surface, metric, source, kStvd8, exact);
  expectWithin(k5, 0.0050, 0.041);  // measured mean 0.00314-0.00360, max 0.0220-0.0294
  expectWithin(k8, 0.0016, 0.031);  // measured mean 0.00089-0.00110, max 0.0098-0.0222
  // Measured: Dijkstra mean 0.0990, max 0.315, 30 times STVD k = 5.
  EXPECT_LT(k5.mean(), 0.1 * d.mean());
}

TEST(SurfaceAccuracy, IcosphereGreatCircleDistances) {
  const GeneratedSurface s = icosphere(4, 2.0);
  const SurfaceDomain surface(s.points, s.faces);
  const RiemannianMetric metric = isotropicSurfaceMetric(surface);
  const VertexId source = 0;
  auto exact = [&](VertexId v) {
    const double c = dot(s.points[v], s.points[source]) / 4.0;
    return 2.0 * std::acos(std::max(-1.0, std::min(1.0, c)));
  };
  const auto d = measure("icosphere r 2", surface, metric, source, kDijkstra, exact);
  const auto k5 = measure("icosphere r 2", surface, metric, source, kStvd5, exact);
  const auto k8 = measure("icosphere r 2", surface, metric, source, kStvd8, exact);
  // The polyhedron is slightly shorter than the sphere: the errors include
  // that (measured min signed -2.0e-4).
  expectWithin(k5, 0.0017, 0.010);  // measured mean 0.00122, max 0.00726
  expectWithin(k8, 0.0006, 0.005);  // measured mean 0.00043, max 0.00355
  EXPECT_LT(k5.mean(), 0.1 * d.mean());  // measured: Dijkstra mean 0.0851, max 0.234
}

/// The paper's observation on a curved, badly shaped mesh: a latitude-
/// longitude sphere, its poles full of needles, seeded near a pole.
TEST(SurfaceAccuracy, OnABadlyShapedSphereAtGammaOneStvdIsClearlyMoreAccurateThanDijkstra) {
  const GeneratedSurface s = uvSphere(96, 48, 1.0);
  const SurfaceDomain surface(s.points, s.faces);
  const RiemannianMetric metric = isotropicSurfaceMetric(surface);
  const VertexId source = 1 + 2 * 96;  // third ring from the north pole
  auto exact = [&](VertexId v) {
    return std::acos(std::max(-1.0, std::min(1.0, dot(s.points[v], s.points[source]))));
  };
  const auto d = measure("uv sphere 96x48", surface, metric, source, kDijkstra, exact);
  const auto k5 = measure("uv sphere 96x48", surface, metric, source, kStvd5, exact);
  const auto k8 = measure("uv sphere 96x48", surface, metric, source, kStvd8, exact);
  expectWithin(k5, 0.0048, 0.085);  // measured mean 0.00339, max 0.0609
  expectWithin(k8, 0.0011, 0.067);  // measured mean 0.00073, max 0.0478
  // Measured: Dijkstra mean 0.0339, max 0.246: ten times STVD k = 5.
  EXPECT_LT(k5.mean(), 0.2 * d.mean());
}

TEST(SurfaceAccuracy, PrismDistancesAreThoseOfTheUnrolledStrip) {
  const int n = 48;
  const GeneratedSurface s = prismMesh(n, 30, 2.0, 0.4, false, 3);
  const SurfaceDomain surface(s.points, s.faces);
  const RiemannianMetric metric = isotropicSurfaceMetric(surface);
  const double perimeter = n * 2.0 * 2.0 * std::sin(kPi / n);
  const VertexId source = 15 * n;
  auto exact = [&](VertexId v) { return unrolledDistance(s.flat[v], s.flat[source], perimeter); };
  const auto d = measure("prism isotropic", surface, metric, source, kDijkstra, exact);
  const auto k5 = measure("prism isotropic", surface, metric, source, kStvd5, exact);
  const auto k8 = measure("prism isotropic", surface, metric, source, kStvd8, exact);
  expectWithin(k5, 0.0049, 0.040);  // measured mean 0.00320-0.00347, max 0.0265-0.0283
  expectWithin(k8, 0.0016, 0.029);  // measured mean 0.00102-0.00110, max 0.0140-0.0209
  EXPECT_LT(k5.mean(), 0.1 * d.mean());  // measured: Dijkstra mean 0.102, max 0.402
}

/// A metric fixed to the cylinder's own directions (around: 3, along the
/// axis: 1) is a constant metric of the development: the tensors must be
/// carried around the curved surface consistently.
TEST(SurfaceAccuracy, PrismWithAxisAlignedAnisotropyMatchesTheUnrolledTensorNorm) {
  const int n = 48;
  const GeneratedSurface s = prismMesh(n, 30, 2.0, 0.4, false, 4);
  const SurfaceDomain surface(s.points, s.faces);
  std::vector<Vec3d> axis(surface.vertexCount(), Vec3d{0, 0, 1});
  const RiemannianMetric metric = vectorFieldMetric(surface, axis, 1.0, 3.0);
  const double perimeter = n * 2.0 * 2.0 * std::sin(kPi / n);
  const VertexId source = 15 * n;
  auto exact = [&](VertexId v) {
    return unrolledDistance(s.flat[v], s.flat[source], perimeter, 3.0, 1.0);
  };
  const auto d = measure("prism around 3 along 1", surface, metric, source, kDijkstra, exact);
  const auto k5 = measure("prism around 3 along 1", surface, metric, source, kStvd5, exact);
  const auto k8 = measure("prism around 3 along 1", surface, metric, source, kStvd8, exact);
  expectWithin(k5, 0.0026, 0.037);  // measured mean 0.00182, max 0.0264
  expectWithin(k8, 0.0013, 0.025);  // measured mean 0.00093-0.00095, max 0.0128-0.0179
  EXPECT_LT(k5.mean(), 0.1 * d.mean());  // measured: Dijkstra mean 0.0674, max 0.413
}

/// On a cylinder one principal curvature vanishes: the curvature metric has
/// anisotropy gamma everywhere, strong around the axis.
TEST(SurfaceAccuracy, CurvatureMetricOnAPrismIsTheUnrolledMetricWithAnisotropyGamma) {
  const int n = 48;
  const GeneratedSurface s = prismMesh(n, 30, 2.0, 0.4, false, 5);
  const SurfaceDomain surface(s.points, s.faces);
  const double gamma = 4.0;
  const RiemannianMetric metric = curvatureMetric(surface, gamma);
  const double perimeter = n * 2.0 * 2.0 * std::sin(kPi / n);
  const VertexId source = 15 * n;
  auto exact = [&](VertexId v) {
    return unrolledDistance(s.flat[v], s.flat[source], perimeter, gamma, 1.0);
  };
  const auto d = measure("prism curvature gamma 4", surface, metric, source, kDijkstra, exact);
  const auto k5 = measure("prism curvature gamma 4", surface, metric, source, kStvd5, exact);
  const auto k8 = measure("prism curvature gamma 4", surface, metric, source, kStvd8, exact);
  expectWithin(k5, 0.0034, 0.060);  // measured mean 0.00242, max 0.0430
  expectWithin(k8, 0.0019, 0.032);  // measured mean 0.00136, max 0.0229
  EXPECT_LT(k5.mean(), 0.1 * d.mean());  // measured: Dijkstra mean 0.0646, max 0.401
}

/// Polygon meshes are used as they are: STVD's neighbours are the quads'
/// edge neighbours (no diagonals), unfolded with the quads' corner angles.
TEST(SurfaceAccuracy, JitteredQuadPlaneWithoutTriangulation) {
  const GeneratedSurface s = badPlane(true);
  const SurfaceDomain surface(s.points, s.faces);
  const RiemannianMetric metric = isotropicSurfaceMetric(surface);
  const VertexId source = nearest(s, 5.0, 5.0);
  auto exact = [&](VertexId v) {
    return std::hypot(s.flat[v][0] - s.flat[source][0], s.flat[v][1] - s.flat[source][1]);
  };
  const auto d = measure("quad plane, gamma 1", surface, metric, source, kDijkstra, exact);
  const auto k5 = measure("quad plane, gamma 1", surface, metric, source, kStvd5, exact);
  const auto k8 = measure("quad plane, gamma 1", surface, metric, source, kStvd8, exact);
  expectWithin(k5, 0.0082, 0.060);  // measured mean 0.00499-0.00584, max 0.0276-0.0433
  expectWithin(k8, 0.0025, 0.061);  // measured mean 0.00146-0.00175, max 0.0150-0.0434
  EXPECT_LT(k5.mean(), 0.1 * d.mean());  // measured: Dijkstra mean 0.226, max 0.417
}

TEST(SurfaceAccuracy, QuadPrismDistancesAreThoseOfTheUnrolledStrip) {
  const int n = 48;
  const GeneratedSurface s = prismMesh(n, 30, 2.0, 0.4, true, 3);
  const SurfaceDomain surface(s.points, s.faces);
  const RiemannianMetric metric = isotropicSurfaceMetric(surface);
  const double perimeter = n * 2.0 * 2.0 * std::sin(kPi / n);
  const VertexId source = 15 * n;
  auto exact = [&](VertexId v) { return unrolledDistance(s.flat[v], s.flat[source], perimeter); };
  const auto d = measure("quad prism isotropic", surface, metric, source, kDijkstra, exact);
  const auto k5 = measure("quad prism isotropic", surface, metric, source, kStvd5, exact);
  const auto k8 = measure("quad prism isotropic", surface, metric, source, kStvd8, exact);
  expectWithin(k5, 0.0084, 0.078);  // measured mean 0.00579-0.00596, max 0.0503-0.0559
  expectWithin(k8, 0.0022, 0.025);  // measured mean 0.00157, max 0.0179
  EXPECT_LT(k5.mean(), 0.1 * d.mean());  // measured: Dijkstra mean 0.294, max 0.414
}

}  // namespace
}  // namespace stvd::test
