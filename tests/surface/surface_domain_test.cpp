// The surface domain: 1-ring frames, boundaries, components, orientation
// repair, rejection of input that is not an orientable 2-manifold, and the
// chain unfolding.
#include <gtest/gtest.h>

#include <cmath>
#include <string>

#include "stvd/propagation/propagation.hpp"
#include "stvd/surface/surface_domain.hpp"
#include "stvd/surface/surface_metrics.hpp"
#include "stvd/surface/surface_propagation.hpp"
#include "surface_meshes.hpp"

namespace stvd::test {
namespace {

std::string errorOf(std::vector<Vec3d> points, const PolygonList& faces) {
  try {
    SurfaceDomain surface(std::move(points), faces);
  } catch (const SurfaceError& e) {
    return e.what();
  }
  return "";
}

TEST(SurfaceDomain, FlatInteriorRingsKeepTheirAnglesAndRunCounterClockwise) {
  const GeneratedSurface s = planeMesh(6, 6, 6.0, 6.0, 0.3, 0.5, false, 1);
  const SurfaceDomain surface(s.points, s.faces);
  for (VertexId v = 0; v < surface.vertexCount(); ++v) {
    const bool boundary = s.flat[v][0] == 0.0 || s.flat[v][1] == 0.0 ||
                          s.flat[v][0] > 5.999 || s.flat[v][1] > 5.999;
    EXPECT_EQ(surface.isBoundary(v), boundary) << v;
    if (!boundary) {
      EXPECT_NEAR(surface.angleSum(v), 2.0 * kPi, 1e-9);
    }
    // Each neighbour's angle in v's frame is its true direction in the
    // plane (counter-clockwise seen from +z), relative to the first.
    const std::uint32_t first = surface.ringBegin(v);
    const auto direction = [&](VertexId w) {
      return std::atan2(s.flat[w][1] - s.flat[v][1], s.flat[w][0] - s.flat[v][0]);
    };
    for (std::uint32_t i = first; i < surface.ringEnd(v); ++i) {
      double expected = direction(surface.ringNeighbor(i)) - direction(surface.ringNeighbor(first));
      expected = std::fmod(expected + 4.0 * kPi, 2.0 * kPi);
      EXPECT_NEAR(std::fmod(surface.ringAngle(i) + 2.0 * kPi, 2.0 * kPi), expected, 1e-5);
    }
    EXPECT_NEAR(surface.normal(v).z, 1.0, 1e-12);
  }
}

TEST(SurfaceDomain, CurvedInteriorRingsAreScaledToAFullTurn) {
  const GeneratedSurface s = icosphere(1, 1.0);
  const SurfaceDomain surface(s.points, s.faces);
  for (VertexId v = 0; v < surface.vertexCount(); ++v) {
    EXPECT_LT(surface.angleSum(v), 2.0 * kPi - 1e-3);
    // The last neighbour sits one corner before the full turn.
    const std::uint32_t last = surface.ringEnd(v) - 1;
    EXPECT_GT(surface.ringAngle(last), 0.0);
    EXPECT_LT(surface.ringAngle(last), 2.0 * kPi);
    EXPECT_FALSE(surface.isBoundary(v));
  }
  EXPECT_EQ(surface.componentCount(), 1u);
}

TEST(SurfaceDomain, ChainUnfoldedOnAPlaneReproducesThePlanarPositions) {
  const GeneratedSurface s = planeMesh(10, 10, 10.0, 10.0, 0.4, 0.5, false, 2);
  const SurfaceDomain surface(s.points, s.faces);
  const RiemannianMetric metric = isotropicSurfaceMetric(surface);
  const PropagationResult r = dijkstra(surface, metric, {0});
  for (VertexId v = 0; v < surface.vertexCount(); ++v) {
    VertexId chain[8];
    int count = 1;
    chain[0] = v;
    while (count < 8 && r.predecessor[chain[count - 1]] != kNoVertex) {
      chain[count] = r.predecessor[chain[count - 1]];
      ++count;
    }
    Vec3f p[8];
    ChainUnfolding<SurfaceDomain>::place(surface, chain, count, p);
    for (int i = 1; i < count; ++i) {
      const double truth = std::hypot(s.flat[chain[i]][0] - s.flat[v][0],
                                      s.flat[chain[i]][1] - s.flat[v][1]);
      EXPECT_NEAR(std::hypot(p[i].x, p[i].y), truth, 1e-4 * (1.0 + truth));
      EXPECT_EQ(p[i].z, 0.f);
    }
  }
}

TEST(SurfaceDomain, MemoryDepthOneIsDijkstraBitForBit) {
  const GeneratedSurface s = prismMesh(16, 8, 1.0, 0.3, false, 9);
  const SurfaceDomain surface(s.points, s.faces);
  std::vector<Vec3d> field(surface.vertexCount(), Vec3d{0, 0.3, 1});
  const RiemannianMetric metric = vectorFieldMetric(surface, field, 1.0, 5.0);
  const PropagationResult d = dijkstra(surface, metric, {3});
  const PropagationResult k1 = shortTermVectorDijkstra(surface, metric, {3}, 1);
  EXPECT_EQ(d.distance, k1.distance);
}

TEST(SurfaceDomain, InconsistentlyOrientedFacesAreReorientedAndGiveTheSameDistances) {
  const GeneratedSurface s = planeMesh(8, 8, 8.0, 8.0, 0.5, 0.5, false, 4);
  PolygonList mixed;
  for (std::size_t f = 0; f < s.faces.faceCount(); ++f) {
    std::vector<VertexId> face(s.faces.faceVertex.begin() + s.faces.faceStart[f],
                               s.faces.faceVertex.begin() + s.faces.faceStart[f + 1]);
    if (f % 3 == 1) std::reverse(face.begin(), face.end());
    mixed.add(face.begin(), face.end());
  }
  const SurfaceDomain a(s.points, s.faces), b(s.points, mixed);
  const auto ra = shortTermVectorDijkstra(a, isotropicSurfaceMetric(a), {40}, 5);
  const auto rb = shortTermVectorDijkstra(b, isotropicSurfaceMetric(b), {40}, 5);
  for (VertexId v = 0; v < a.vertexCount(); ++v) EXPECT_NEAR(ra.distance[v], rb.distance[v], 1e-5);
}

/// Every array of the two surfaces, entry for entry and bit for bit.
void expectSameSurface(const SurfaceDomain& a, const SurfaceDomain& b) {
  ASSERT_EQ(a.vertexCount(), b.vertexCount());
  EXPECT_EQ(a.faces().faceVertex, b.faces().faceVertex);
  EXPECT_EQ(a.component(), b.component());
  for (VertexId v = 0; v < a.vertexCount(); ++v) {
    ASSERT_EQ(a.ringBegin(v), b.ringBegin(v));
    ASSERT_EQ(a.ringEnd(v), b.ringEnd(v));
    EXPECT_EQ(a.isBoundary(v), b.isBoundary(v));
    EXPECT_EQ(a.angleSum(v), b.angleSum(v));
    EXPECT_EQ(a.normal(v).x, b.normal(v).x);
    EXPECT_EQ(a.normal(v).z, b.normal(v).z);
    EXPECT_EQ(a.tangent(v).y, b.tangent(v).y);
    for (std::uint32_t i = a.ringBegin(v); i < a.ringEnd(v); ++i) {
      EXPECT_EQ(a.ringNeighbor(i), b.ringNeighbor(i));
      EXPECT_EQ(a.ringAngle(i), b.ringAngle(i));
      EXPECT_EQ(a.ringEdgeX(i), b.ringEdgeX(i));
      EXPECT_EQ(a.ringDirectionY(i), b.ringDirectionY(i));
      EXPECT_EQ(a.ringCorner(i).cos, b.ringCorner(i).cos);
      EXPECT_EQ(a.ringCorner(i).sin, b.ringCorner(i).sin);
      EXPECT_EQ(a.ringCorner(i).length, b.ringCorner(i).length);
      EXPECT_EQ(a.ringFace(i), b.ringFace(i));
    }
  }
}

TEST(SurfaceDomain, ALargeSurfaceWithMixedOrientationsIsBuiltAsTheConsistentOne) {
  // 40,962 vertices: built in blocks on two threads; the mixed copy takes
  // the path that matches edge sides and flips faces to agree with face 0.
  const GeneratedSurface s = icosphere(6, 80.0);
  PolygonList mixed;
  for (std::size_t f = 0; f < s.faces.faceCount(); ++f) {
    std::vector<VertexId> face(s.faces.faceVertex.begin() + s.faces.faceStart[f],
                               s.faces.faceVertex.begin() + s.faces.faceStart[f + 1]);
    if (f % 3 == 1) std::reverse(face.begin(), face.end());
    mixed.add(face.begin(), face.end());
  }
  expectSameSurface(SurfaceDomain(s.points, s.faces), SurfaceDomain(s.points, mixed));
}

TEST(SurfaceDomain, OnALargeSurfaceTheLowestVertexThatIsNoFanIsNamed) {
  // Two extra triangles touch the sphere at one vertex each, far apart in
  // the vertex order (different blocks of the parallel build).
  GeneratedSurface s = icosphere(6, 80.0);
  const VertexId extra = static_cast<VertexId>(s.points.size());
  for (int i = 0; i < 4; ++i) s.points.push_back({200.0 + i, double(i % 2), 0.0});
  s.faces.add({30000, extra, extra + 1});
  s.faces.add({20000, extra + 2, extra + 3});
  const std::string e = errorOf(s.points, s.faces);
  EXPECT_NE(e.find("vertex 20000 is not a 2-manifold vertex"), std::string::npos) << e;
}

TEST(SurfaceDomain, AVertexOfManyFacesHasItsWholeFanInOrder) {
  // A flat fan of 40 triangles around vertex 0 (more than a linear search
  // covers), closed and, without its last triangle, open.
  const int count = 40;
  std::vector<Vec3d> p{{0, 0, 0}};
  for (int k = 0; k < count; ++k) p.push_back({std::cos(2 * kPi * k / count), std::sin(2 * kPi * k / count), 0});
  for (const bool closed : {true, false}) {
    PolygonList f;
    for (int k = 0; k < (closed ? count : count - 1); ++k)
      f.add({0, VertexId(1 + k), VertexId(1 + (k + 1) % count)});
    const SurfaceDomain surface(p, f);
    EXPECT_EQ(surface.isBoundary(0), !closed);
    ASSERT_EQ(surface.ringEnd(0) - surface.ringBegin(0), std::uint32_t(count));
    for (int k = 0; k < count; ++k) {
      EXPECT_EQ(surface.ringNeighbor(surface.ringBegin(0) + k), VertexId(1 + k)) << closed;
      EXPECT_NEAR(surface.ringAngle(surface.ringBegin(0) + k), 2 * kPi * k / count, 1e-5) << closed;
    }
    EXPECT_NEAR(surface.angleSum(0), closed ? 2 * kPi : 2 * kPi * (count - 1) / count, 1e-9);
  }
}

TEST(SurfaceDomain, SeveralComponentsAndIsolatedVerticesAreUnreachableFromTheOther) {
  GeneratedSurface s = planeMesh(3, 3, 3.0, 3.0, 1.0, 0.0, false, 1);
  const VertexId offset = static_cast<VertexId>(s.points.size());
  for (VertexId v = 0; v < offset; ++v) s.points.push_back(s.points[v] + Vec3d{10, 0, 0});
  const std::size_t faceCount = s.faces.faceCount();
  for (std::size_t f = 0; f < faceCount; ++f) {
    std::vector<VertexId> face;
    for (std::uint32_t c = s.faces.faceStart[f]; c < s.faces.faceStart[f + 1]; ++c)
      face.push_back(s.faces.faceVertex[c] + offset);
    s.faces.add(face.begin(), face.end());
  }
  s.points.push_back({0, 0, 5});  // isolated
  const SurfaceDomain surface(s.points, s.faces);
  EXPECT_EQ(surface.componentCount(), 3u);
  const auto r = shortTermVectorDijkstra(surface, isotropicSurfaceMetric(surface), {0}, 5);
  for (VertexId v = 0; v < offset; ++v) EXPECT_TRUE(std::isfinite(r.distance[v]));
  for (VertexId v = offset; v < surface.vertexCount(); ++v) EXPECT_EQ(r.distance[v], kUnreachable);
}

TEST(SurfaceDomain, AnEdgeOfThreeFacesIsRejectedNamingTheEdge) {
  PolygonList f;
  f.add({0, 1, 2});
  f.add({1, 0, 3});
  f.add({0, 1, 4});
  const std::string e = errorOf({{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, -1, 0}, {0, 0, 1}}, f);
  EXPECT_NE(e.find("edge (0, 1) is shared by 3 faces"), std::string::npos) << e;
}

TEST(SurfaceDomain, TwoFansAtOneVertexAreRejectedNamingTheVertex) {
  PolygonList f;  // two triangles touching only at vertex 0 (a bow tie)
  f.add({0, 1, 2});
  f.add({0, 3, 4});
  const std::string e =
      errorOf({{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {-1, 0, 0}, {-1, -1, 0}}, f);
  EXPECT_NE(e.find("vertex 0 is not a 2-manifold vertex"), std::string::npos) << e;
}

TEST(SurfaceDomain, AMoebiusStripIsRejectedAsNotOrientable) {
  const int n = 8;
  std::vector<Vec3d> p;
  for (int i = 0; i < n; ++i) {
    const double t = 2.0 * kPi * i / n, h = 0.3;
    const Vec3d c{std::cos(t), std::sin(t), 0};
    const Vec3d w = std::cos(t / 2) * c + std::sin(t / 2) * Vec3d{0, 0, 1};
    p.push_back(c + h * w);
    p.push_back(c - h * w);
  }
  PolygonList f;
  for (int i = 0; i < n; ++i) {
    const VertexId a = 2 * i, b = 2 * i + 1;
    // The last quad joins the strip with a half twist.
    const VertexId c = i + 1 < n ? 2 * (i + 1) + 1 : 0, d = i + 1 < n ? 2 * (i + 1) : 1;
    f.add({a, b, c, d});
  }
  EXPECT_NE(errorOf(p, f).find("not orientable"), std::string::npos) << errorOf(p, f);
}

TEST(SurfaceDomain, BadFacesAreRejectedNamingTheFace) {
  const std::vector<Vec3d> p{{0, 0, 0}, {1, 0, 0}, {0, 1, 0}};
  PolygonList outOfRange, repeated, tooSmall;
  outOfRange.add({0, 1, 7});
  repeated.add({0, 1, 1});
  tooSmall.add({0, 1});
  EXPECT_NE(errorOf(p, outOfRange).find("face 0 refers to vertex 7 but there are 3 vertices"),
            std::string::npos);
  EXPECT_NE(errorOf(p, repeated).find("face 0 uses a vertex twice"), std::string::npos);
  EXPECT_NE(errorOf(p, tooSmall).find("face 0 has 2 vertices"), std::string::npos);
}

TEST(SurfaceMetrics, LocalTensorsAndWorldTensorsDescribeTheSameMetric) {
  const GeneratedSurface s = icosphere(1, 1.0);
  const SurfaceDomain surface(s.points, s.faces);
  std::vector<std::array<double, 3>> local(surface.vertexCount(), {4.0, 1.0, 2.0});
  const RiemannianMetric m = surfaceMetricFromLocalTensors(surface, local);
  for (VertexId v = 0; v < surface.vertexCount(); ++v) {
    const Vec3f t1 = toFloat(surface.tangent(v));
    const Vec3d n = surface.normal(v), t = surface.tangent(v);
    const Vec3f t2 = toFloat(Vec3d{n.y * t.z - n.z * t.y, n.z * t.x - n.x * t.z, n.x * t.y - n.y * t.x});
    EXPECT_NEAR(m[v].quadraticForm(t1), 4.0, 1e-5);
    EXPECT_NEAR(dot(t1, m[v].apply(t2)), 1.0, 1e-5);
    EXPECT_NEAR(m[v].quadraticForm(t2), 2.0, 1e-5);
    // The world tensor's tangential part gives back the same tensor.
    const SymTensor3 again = tangentialPart(surface, v, m[v]);
    EXPECT_NEAR(again.quadraticForm(t1), 4.0, 1e-4);
  }
  local[5] = {1.0, 2.0, 1.0};  // indefinite
  try {
    surfaceMetricFromLocalTensors(surface, local);
    FAIL() << "an indefinite tensor was accepted";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("vertex 5"), std::string::npos) << e.what();
  }
}

TEST(SurfaceMetrics, PrincipalCurvaturesOfACylinderAndASphere) {
  const GeneratedSurface prism = prismMesh(64, 20, 2.0, 0.2, false, 6);
  const SurfaceDomain cylinder(prism.points, prism.faces);
  const auto pc = principalCurvatures(cylinder);
  for (VertexId v = 0; v < cylinder.vertexCount(); ++v) {
    // Measured largest deviations: 0.0032, 0.00017 and 1.8e-7.
    EXPECT_NEAR(std::abs(pc[v].kappaMax), 0.5, 0.0045) << v;  // 1 / radius
    EXPECT_NEAR(pc[v].kappaMin, 0.0, 0.00025) << v;
    EXPECT_NEAR(std::abs(pc[v].directionMin.z), 1.0, 1e-6) << v;  // along the axis
  }
  const GeneratedSurface ico = icosphere(3, 4.0);
  const SurfaceDomain sphere(ico.points, ico.faces);
  for (const PrincipalCurvature& c : principalCurvatures(sphere)) {
    // Measured largest deviations: 0.00135 and 0.00067.
    EXPECT_NEAR(std::abs(c.kappaMax), 0.25, 0.0019);
    EXPECT_NEAR(std::abs(c.kappaMin), 0.25, 0.001);
  }
}

TEST(SurfaceMetrics, FaceTensorsAreAveragedToTheVerticesByCornerAngle) {
  // A unit square split into two triangles: vertex 0 has corners of 45 and
  // 45 degrees, vertex 1 one corner of 90 degrees (in face 0 only).
  PolygonList f;
  f.add({0, 1, 2});
  f.add({0, 2, 3});
  const SurfaceDomain surface({{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}}, f);
  const SymTensor3 a{4, 0, 0, 1, 0, 1}, b{2, 0, 0, 3, 0, 1};
  const RiemannianMetric m = surfaceMetricFromFaceTensors(surface, {a, b});
  const Vec3f x{1, 0, 0}, y{0, 1, 0};
  EXPECT_NEAR(m[1].quadraticForm(x), 4.0, 1e-5);  // face 0 alone
  EXPECT_NEAR(m[3].quadraticForm(y), 3.0, 1e-5);  // face 1 alone
  EXPECT_NEAR(m[0].quadraticForm(x), 3.0, 1e-5);  // equal corners: the mean
  EXPECT_NEAR(m[0].quadraticForm(y), 2.0, 1e-5);
  EXPECT_THROW(surfaceMetricFromFaceTensors(surface, {a}), std::invalid_argument);
}

}  // namespace
}  // namespace stvd::test
