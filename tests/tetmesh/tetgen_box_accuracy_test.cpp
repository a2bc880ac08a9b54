// Propagation on an unstructured tetrahedral mesh made by TetGen (the
// setting of section 6.2 and Figure 9 of Campen, Heistermann, Kobbelt 2013):
// a quality mesh of a box with more than 50,000 vertices, under
//  - a constant metric of anisotropy gamma = 12 along an oblique axis, whose
//    exact distance is ||x - s||_G (the box is convex), and
//  - a curved pull-back metric G = J^T J of a smooth map phi, whose exact
//    distance is |phi(x) - phi(s)| where the straight segment between the
//    images stays in the image of the box.
// STVD measures 3D sums of mesh edges directly; Dijkstra is held to the
// mesh's edge directions. And a quality mesh of an L-shaped prism, which is
// not convex: no distance may cut its notch.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <string>
#include <utility>
#include <vector>

#include "../core/exact_metrics.hpp"
#include "../core/relative_error.hpp"
#include "../core/scenes.hpp"
#include "l_shaped_prism_surface.hpp"
#include "stvd/propagation/propagation.hpp"
#include "stvd/tetgen/tetrahedralize.hpp"
#include "stvd/cell_mesh/cell_mesh_propagation.hpp"

namespace stvd {
namespace {

using test::RelativeErrors;

const Vec3d kBoxLow{-20.0, -16.0, -12.0};
const Vec3d kBoxHigh{20.0, 16.0, 12.0};

/// The TetGen quality mesh of the box (radius-edge ratio 1.4, tetrahedra of
/// at most 0.2 mm^3), made once per test program.
const tetmesh::TetMesh& boxMesh() {
  static const tetmesh::TetMesh mesh = [] {
    tetgen::TetrahedralizeOptions options;
    options.quality = 1.4;
    options.maxVolume = 0.2;
    return tetgen::tetrahedralizeSurface(tetgen::boxSurface(kBoxLow, kBoxHigh), options, "box");
  }();
  return mesh;
}

VertexId vertexNearest(const std::vector<Vec3d>& points, Vec3d p) {
  VertexId best = 0;
  for (VertexId v = 1; v < points.size(); ++v)
    if (dot(points[v] - p, points[v] - p) < dot(points[best] - p, points[best] - p)) best = v;
  return best;
}

PropagationResult run(const CellMeshDomain& mesh, const RiemannianMetric& metric, VertexId source,
                      Method method, int k, int anyAngleAncestors = kDefaultAnyAngleAncestors) {
  PropagationOptions o;
  o.method = method;
  o.k = k;
  o.anyAngleAncestors = anyAngleAncestors;
  return propagate(mesh, metric, {source}, o);
}

TEST(TetGenBoxMesh, HasMoreThanFiftyThousandVerticesAndValidTetrahedra) {
  const tetmesh::TetMesh& mesh = boxMesh();
  EXPECT_GE(mesh.vertexCount(), 50000u);
  for (const auto& t : mesh.tets)
    ASSERT_GT(tetmesh::signedVolume(mesh.points[t[0]], mesh.points[t[1]], mesh.points[t[2]], mesh.points[t[3]]), 0.0);
  for (const Vec3d& p : mesh.points) {
    ASSERT_GE(p.x, kBoxLow.x);
    ASSERT_LE(p.x, kBoxHigh.x);
  }
}

// Measured (Release, x86-64) from a source near the centre over the other
// 55,167 vertices (TetGen 1.5 of Debian 12 makes the same mesh every time):
//   Dijkstra:                         mean 0.136    max 3.26
//   STVD, defaults (k = 6, segment):  mean 0.00672  max 0.203  (Dijkstra / STVD: 20.3)
// (k = 8: 0.00482; the paper's rule at k = 8: 0.00459, largest-norm rule
// 0.00465.) Each bound is about 1.4 times the measured figure (the ratio's
// 1.4 times below it); the mean bound also meets the 1 %.
constexpr double kConstantDijkstraMeanBound = 0.19;
constexpr double kConstantDijkstraMaxBound = 4.6;
constexpr double kConstantStvdMeanBound = 0.0094;
constexpr double kConstantStvdMaxBound = 0.285;
constexpr double kConstantMinImprovement = 14.0;

class ConstantGamma12 {
 public:
  ConstantGamma12()
      : mesh_(CellMeshDomain::fromTetrahedra(boxMesh().points, boxMesh().tets)),
        g_(test::uniaxialTensor(12.0, {0.55, -0.45, 0.7})),
        metric_(RiemannianMetric::constant(mesh_.vertexCount(), test::toSymTensor(g_))),
        source_(vertexNearest(boxMesh().points, {1.3, -0.7, 0.4})) {}

  RelativeErrors measure(Method method, int k, const std::string& label) const {
    const PropagationResult r = run(mesh_, metric_, source_, method, k);
    RelativeErrors e;
    const Vec3d s = mesh_.physicalPoint(source_);
    for (VertexId v = 0; v < mesh_.vertexCount(); ++v)
      if (v != source_) e.add(r.distance[v], test::tensorNorm(g_, mesh_.physicalPoint(v) - s));
    test::reportMeasurement("TetGen box gamma 12 " + label, e);
    EXPECT_EQ(e.unreached(), 0u);
    // A constant norm: no edge polygon from the source undercuts the straight line.
    EXPECT_GE(e.minSigned(), -1e-5) << label;
    return e;
  }

 private:
  CellMeshDomain mesh_;
  test::Mat3 g_;
  RiemannianMetric metric_;
  VertexId source_;
};

TEST(TetGenBoxMesh, ConstantGamma12MetricStvdIsWithinOnePercentAndFarBetterThanDijkstra) {
  ASSERT_EQ(defaultMemoryDepth<CellMeshDomain>(), 6) << "re-measure the STVD bounds in this file";
  ASSERT_EQ(kDefaultChainMeasure, ChainMeasure::Segment) << "re-measure the STVD bounds in this file";
  const ConstantGamma12 scene;
  const RelativeErrors dijkstra = scene.measure(Method::Dijkstra, 1, "Dijkstra");
  EXPECT_LE(dijkstra.mean(), kConstantDijkstraMeanBound);
  EXPECT_LE(dijkstra.max(), kConstantDijkstraMaxBound);
  const RelativeErrors stvd = scene.measure(Method::ShortTermVectorDijkstra, defaultMemoryDepth<CellMeshDomain>(), "STVD k=6");
  EXPECT_LE(stvd.mean(), kConstantStvdMeanBound);
  EXPECT_LE(stvd.max(), kConstantStvdMaxBound);
  EXPECT_GE(dijkstra.mean(), kConstantMinImprovement * stvd.mean());
}

/// phi of exact_metrics.hpp with gamma = 12 about the box centre, shear
/// slopes a * w = 0.26 (the strong axis turns by up to 15 degrees across the
/// box, at most 0.017 rad per mm), as in the grid's pull-back specification.
test::TriangularPullbackMap curvedMap() {
  test::TriangularPullbackMap map;
  map.r = test::rotation({0.4, 0.3, -1.0}, 0.9);
  map.centre = {0.0, 0.0, 0.0};
  map.gamma = 12.0;
  map.a1 = 4.0;
  map.w1 = 2.0 * test::kPi / 96.0;
  map.a3 = 4.0;
  map.w3 = 2.0 * test::kPi / 96.0;
  return map;
}

/// Whether the straight segment a -> b in phi's image maps back into the box:
/// samples 0.25 apart in the image are at most 0.45 mm apart in the box
/// (|d phi^-1| <= 1.8 for these slopes), below the mesh's edge length.
bool segmentStaysInBox(const test::TriangularPullbackMap& map, Vec3d a, Vec3d b) {
  const int samples = std::max(2, static_cast<int>(std::ceil(norm(b - a) / 0.25)));
  for (int n = 1; n <= samples; ++n) {
    const Vec3d x = map.inverse(a + (static_cast<double>(n) / samples) * (b - a));
    if (x.x < kBoxLow.x - 1e-9 || x.x > kBoxHigh.x + 1e-9 || x.y < kBoxLow.y - 1e-9 || x.y > kBoxHigh.y + 1e-9 ||
        x.z < kBoxLow.z - 1e-9 || x.z > kBoxHigh.z + 1e-9)
      return false;
  }
  return true;
}

/// The curved metric on the box mesh, with the exact distance of every
/// vertex whose image segment stays in the image of the box.
class CurvedGamma12 {
 public:
  CurvedGamma12()
      : mesh_(CellMeshDomain::fromTetrahedra(boxMesh().points, boxMesh().tets)),
        source_(vertexNearest(boxMesh().points, {1.3, -0.7, 0.4})),
        exact_(mesh_.vertexCount(), -1.0) {
    const test::TriangularPullbackMap map = curvedMap();
    std::vector<SymTensor3> tensors(mesh_.vertexCount());
    for (VertexId v = 0; v < mesh_.vertexCount(); ++v) tensors[v] = test::toSymTensor(map.metric(mesh_.physicalPoint(v)));
    metric_ = RiemannianMetric(std::move(tensors));
    const Vec3d imageOfSource = map(mesh_.physicalPoint(source_));
    for (VertexId v = 0; v < mesh_.vertexCount(); ++v) {
      const Vec3d image = map(mesh_.physicalPoint(v));
      if (v != source_ && segmentStaysInBox(map, imageOfSource, image)) {
        exact_[v] = norm(image - imageOfSource);
        ++exactCount_;
      }
    }
  }
  std::size_t exactCount() const { return exactCount_; }
  VertexId vertexCount() const { return mesh_.vertexCount(); }

  RelativeErrors measure(Method method, int k, const std::string& label,
                         int anyAngleAncestors = kDefaultAnyAngleAncestors) const {
    const PropagationResult r = run(mesh_, metric_, source_, method, k, anyAngleAncestors);
    RelativeErrors e;
    for (VertexId v = 0; v < mesh_.vertexCount(); ++v)
      if (exact_[v] > 0.0) e.add(r.distance[v], exact_[v]);
    test::reportMeasurement("TetGen box pull-back gamma 12 " + label, e);
    EXPECT_EQ(e.unreached(), 0u);
    return e;
  }

 private:
  CellMeshDomain mesh_;
  RiemannianMetric metric_;
  VertexId source_;
  std::vector<double> exact_;
  std::size_t exactCount_ = 0;
};

const CurvedGamma12& curvedScene() {
  static const CurvedGamma12 scene;
  return scene;
}

// Measured (Release, x86-64) over the vertices with a closed-form distance:
//   Dijkstra:                         mean 0.123    max 2.80
//   STVD, defaults (k = 6, segment):  mean 0.00738  max 0.344  (most negative -0.0006)
// (k = 8: mean 0.00561, max 0.135; the paper's rule at k = 8: mean 0.00598,
// most negative -0.016; the largest-norm rule 0.0134.) Bounds about 1.4
// times the measured figures.
constexpr double kCurvedDijkstraMeanBound = 0.17;
constexpr double kCurvedDijkstraMaxBound = 4.0;
constexpr double kCurvedStvdMeanBound = 0.0103;
constexpr double kCurvedStvdMaxBound = 0.48;
/// Dijkstra's mean error over STVD's (defaults): measured 16.7.
constexpr double kCurvedMinImprovement = 11.9;

TEST(TetGenBoxMesh, CurvedPullbackMetricStvdIsWithinItsBoundsAndFarBetterThanDijkstra) {
  ASSERT_EQ(defaultMemoryDepth<CellMeshDomain>(), 6) << "re-measure the STVD bounds in this file";
  ASSERT_EQ(kDefaultChainMeasure, ChainMeasure::Segment) << "re-measure the STVD bounds in this file";
  const CurvedGamma12& scene = curvedScene();
  std::printf("[ measured ] vertices with a closed-form distance: %zu of %u\n", scene.exactCount(),
              scene.vertexCount());
  // The shear is mild enough that the image of the box stays star-shaped
  // about the source's image: (almost) every vertex has a closed form.
  EXPECT_GE(scene.exactCount(), scene.vertexCount() * 9 / 10);
  const RelativeErrors dijkstra = scene.measure(Method::Dijkstra, 1, "Dijkstra");
  EXPECT_LE(dijkstra.mean(), kCurvedDijkstraMeanBound);
  EXPECT_LE(dijkstra.max(), kCurvedDijkstraMaxBound);
  const RelativeErrors stvd = scene.measure(Method::ShortTermVectorDijkstra, defaultMemoryDepth<CellMeshDomain>(), "STVD k=6");
  EXPECT_LE(stvd.mean(), kCurvedStvdMeanBound);
  EXPECT_LE(stvd.max(), kCurvedStvdMaxBound);
  EXPECT_GE(dijkstra.mean(), kCurvedMinImprovement * stvd.mean());
}

// The segment measure converges with k where the chain rules stop
// improving (the paper's rule rises again beyond k = 8 here): the chain of
// edges alone (no any-angle ancestor, which reaches past k edges, so that
// with it the error depends little on k: 0.0061, 0.0046, 0.0042, 0.0041,
// 0.0042). Measured means for k = 2, 5, 8, 12, 16: 0.0358, 0.0085, 0.0056,
// 0.0044, 0.0037.
TEST(TetGenBoxMesh, CurvedPullbackErrorFallsWithMemoryDepth) {
  double previous = 1.0;
  for (int k : {2, 5, 8, 12, 16}) {
    const double mean =
        curvedScene().measure(Method::ShortTermVectorDijkstra, k, "STVD k=" + std::to_string(k) + ", chain alone", 0).mean();
    EXPECT_LT(mean, previous) << "k = " << k;
    previous = mean;
  }
}

// The L-shaped prism (l_shaped_prism_surface.hpp), meshed by TetGen, under
// the constant metric diag(1, 4, 2.25).

// Measured (Release, x86-64), 4,873 vertices: mean error 0.119 for
// Dijkstra, 0.00412 (max 0.062) for STVD with the defaults (k = 6,
// segment), 420 candidates refused; no vertex below the distance around the
// notch for any method. The bound is 1.4 times the measured mean.
TEST(TetGenLShapedMesh, NoDistanceIsShorterThanThePathAroundTheNotch) {
  ASSERT_EQ(defaultMemoryDepth<CellMeshDomain>(), 6) << "re-measure the bound of this test";
  tetgen::TetrahedralizeOptions options;
  options.quality = 1.4;
  options.maxVolume = 0.1;
  const tetmesh::TetMesh prism = tetgen::tetrahedralizeSurface(test::lShapedPrismSurface(), options, "L-shaped prism");
  const CellMeshDomain mesh = CellMeshDomain::fromTetrahedra(prism.points, prism.tets);
  EXPECT_GT(mesh.tetrahedra()->nonConvexEdgeCount(), 0u);
  const double a = 1.0, b = 2.0, c = 1.5;
  const RiemannianMetric metric =
      RiemannianMetric::constant(mesh.vertexCount(), SymTensor3{float(a * a), 0.f, 0.f, float(b * b), 0.f, float(c * c)});
  const VertexId source = vertexNearest(prism.points, {15.0, 4.0, 1.0});
  for (const auto& [method, measure] : {std::pair{Method::Dijkstra, kDefaultChainMeasure},
                                        std::pair{Method::ShortTermVectorDijkstra, ChainMeasure::Segment},
                                        std::pair{Method::ShortTermVectorDijkstra, ChainMeasure::ProjectionWeighted},
                                        std::pair{Method::ShortTermVectorDijkstra, ChainMeasure::LargestEdgeNorm}}) {
    PropagationOptions o;
    o.method = method;
    o.chainMeasure = measure;
    const PropagationResult r = propagate(mesh, metric, {source}, o);
    const std::string label = method == Method::Dijkstra ? "Dijkstra" : std::string("STVD ") + chainMeasureName(measure);
    RelativeErrors e;
    std::size_t below = 0;
    for (VertexId v = 0; v < mesh.vertexCount(); ++v) {
      if (v == source) continue;
      const double exact = test::lShapedPrismDistance(8.0, prism.points[source], prism.points[v], a, b, c);
      e.add(r.distance[v], exact);
      below += r.distance[v] < exact * (1.0 - 1e-5) ? 1 : 0;
    }
    test::reportMeasurement("TetGen L-shaped prism " + label, e);
    std::printf("[ measured ] %s: %llu candidates refused\n", label.c_str(),
                static_cast<unsigned long long>(r.refusedCandidates));
    EXPECT_EQ(e.unreached(), 0u) << label;
    EXPECT_EQ(below, 0u) << label;
    if (method == Method::ShortTermVectorDijkstra) {
      EXPECT_GT(r.refusedCandidates, 0u) << label;
    }
    if (method == Method::ShortTermVectorDijkstra && measure == kDefaultChainMeasure) {
      EXPECT_LE(e.mean(), 0.0058);
    }
  }
}

}  // namespace
}  // namespace stvd
