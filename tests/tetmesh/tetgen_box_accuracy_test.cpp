// Propagation on an unstructured tetrahedral mesh made by TetGen (the
// setting of section 6.2 and Figure 9 of Campen, Heistermann, Kobbelt 2013):
// a quality mesh of a box with more than 50,000 vertices, under
//  - a constant metric of anisotropy gamma = 12 along an oblique axis, whose
//    exact distance is ||x - s||_G (the box is convex), and
//  - a curved pull-back metric G = J^T J of a smooth map phi, whose exact
//    distance is |phi(x) - phi(s)| where the straight segment between the
//    images stays in the image of the box.
// STVD measures 3D sums of mesh edges directly; Dijkstra is held to the
// mesh's edge directions.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

#include "../core/exact_metrics.hpp"
#include "../core/relative_error.hpp"
#include "stvd/propagation.hpp"
#include "stvd/tetgen/tetrahedralize.hpp"

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
                      Method method, int k) {
  PropagationOptions o;
  o.method = method;
  o.k = k;
  // The paper's chain rule, which the figures below were measured with:
  // meshes have no segment measure of their own yet (the default falls back
  // to the largest-norm rule there; CandidatePath).
  o.chainMeasure = ChainMeasure::ProjectionWeighted;
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
//   Dijkstra:            mean 0.136    max 3.26
//   STVD k = 8:          mean 0.00465  max 0.117   (Dijkstra / STVD: 29)
//   STVD k = 5 default:  mean 0.00846  max 0.305
// (k = 3: 0.0185, k = 12: 0.0028.) Each bound is about 1.4 times the
// measured figure; the k = 8 mean bound also meets the 1 %.
constexpr double kConstantDijkstraMeanBound = 0.19;
constexpr double kConstantDijkstraMaxBound = 4.6;
constexpr double kConstantStvdMeanBound = 0.0065;
constexpr double kConstantStvdMaxBound = 0.165;
constexpr double kConstantStvdDefaultMeanBound = 0.012;
constexpr double kConstantStvdDefaultMaxBound = 0.43;
constexpr double kConstantMinImprovement = 20.0;

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
  const ConstantGamma12 scene;
  const RelativeErrors dijkstra = scene.measure(Method::Dijkstra, 1, "Dijkstra");
  EXPECT_LE(dijkstra.mean(), kConstantDijkstraMeanBound);
  EXPECT_LE(dijkstra.max(), kConstantDijkstraMaxBound);
  const RelativeErrors stvd = scene.measure(Method::ShortTermVectorDijkstra, 8, "STVD k=8");
  EXPECT_LE(stvd.mean(), kConstantStvdMeanBound);
  EXPECT_LE(stvd.max(), kConstantStvdMaxBound);
  EXPECT_GE(dijkstra.mean(), kConstantMinImprovement * stvd.mean());
  ASSERT_EQ(kDefaultMemoryDepth, 6) << "re-measure the default-k bounds in this file";
  ASSERT_EQ(kDefaultChainMeasure, ChainMeasure::Segment) << "re-measure the default-k bounds in this file";
  const RelativeErrors byDefault = scene.measure(Method::ShortTermVectorDijkstra, kDefaultMemoryDepth, "STVD k=5");
  EXPECT_LE(byDefault.mean(), kConstantStvdDefaultMeanBound);
  EXPECT_LE(byDefault.max(), kConstantStvdDefaultMaxBound);
  EXPECT_GE(dijkstra.mean(), 10.0 * byDefault.mean());
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

// Measured (Release, x86-64) over the vertices with a closed-form distance:
//   Dijkstra:            mean 0.123    max 2.80
//   STVD k = 8:          mean 0.00598  max 0.126  (most negative -0.016)
//   STVD k = 5 default:  mean 0.00851  max 0.297  (most negative -0.006)
// (k = 3: 0.0177, k = 12: 0.0065: longer chains start to underestimate on a
// curved metric, as on grids.) Bounds about 1.4 times the measured figures.
constexpr double kCurvedDijkstraMeanBound = 0.17;
constexpr double kCurvedDijkstraMaxBound = 4.0;
constexpr double kCurvedStvdMeanBound = 0.0085;
constexpr double kCurvedStvdMaxBound = 0.18;
constexpr double kCurvedStvdDefaultMeanBound = 0.012;
constexpr double kCurvedStvdDefaultMaxBound = 0.42;
/// Dijkstra's mean error over STVD's (k = 8): measured 20.6.
constexpr double kCurvedMinImprovement = 14.0;

TEST(TetGenBoxMesh, CurvedPullbackMetricStvdIsWithinItsBoundsAndFarBetterThanDijkstra) {
  const tetmesh::TetMesh& box = boxMesh();
  const CellMeshDomain mesh = CellMeshDomain::fromTetrahedra(box.points, box.tets);
  const test::TriangularPullbackMap map = curvedMap();
  std::vector<SymTensor3> tensors(mesh.vertexCount());
  for (VertexId v = 0; v < mesh.vertexCount(); ++v) tensors[v] = test::toSymTensor(map.metric(box.points[v]));
  const RiemannianMetric metric(std::move(tensors));
  const VertexId source = vertexNearest(box.points, {1.3, -0.7, 0.4});
  const Vec3d imageOfSource = map(box.points[source]);
  std::vector<double> exact(mesh.vertexCount(), -1.0);
  std::size_t exactCount = 0;
  for (VertexId v = 0; v < mesh.vertexCount(); ++v) {
    const Vec3d image = map(box.points[v]);
    if (v != source && segmentStaysInBox(map, imageOfSource, image)) {
      exact[v] = norm(image - imageOfSource);
      ++exactCount;
    }
  }
  std::printf("[ measured ] vertices with a closed-form distance: %zu of %u\n", exactCount, mesh.vertexCount());
  // The shear is mild enough that the image of the box stays star-shaped
  // about the source's image: (almost) every vertex has a closed form.
  EXPECT_GE(exactCount, mesh.vertexCount() * 9 / 10);
  auto measure = [&](Method method, int k, const std::string& label) {
    const PropagationResult r = run(mesh, metric, source, method, k);
    RelativeErrors e;
    for (VertexId v = 0; v < mesh.vertexCount(); ++v)
      if (exact[v] > 0.0) e.add(r.distance[v], exact[v]);
    test::reportMeasurement("TetGen box pull-back gamma 12 " + label, e);
    EXPECT_EQ(e.unreached(), 0u);
    return e;
  };
  const RelativeErrors dijkstra = measure(Method::Dijkstra, 1, "Dijkstra");
  EXPECT_LE(dijkstra.mean(), kCurvedDijkstraMeanBound);
  EXPECT_LE(dijkstra.max(), kCurvedDijkstraMaxBound);
  const RelativeErrors stvd = measure(Method::ShortTermVectorDijkstra, 8, "STVD k=8");
  EXPECT_LE(stvd.mean(), kCurvedStvdMeanBound);
  EXPECT_LE(stvd.max(), kCurvedStvdMaxBound);
  EXPECT_GE(dijkstra.mean(), kCurvedMinImprovement * stvd.mean());
  const RelativeErrors byDefault = measure(Method::ShortTermVectorDijkstra, kDefaultMemoryDepth, "STVD k=5");
  EXPECT_LE(byDefault.mean(), kCurvedStvdDefaultMeanBound);
  EXPECT_LE(byDefault.max(), kCurvedStvdDefaultMaxBound);
}

}  // namespace
}  // namespace stvd
