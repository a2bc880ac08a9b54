// Splitting non-manifold meshes into manifold sheets, on the smallest
// meshes of each kind (the exact references on real meshes are in
// non_manifold_exact_test.cpp): which vertices are copied, which faces are
// cut off, that the result is a SurfaceDomain, and that distances pass
// between the sheets at the split vertices and only there.
#include <gtest/gtest.h>

#include <cmath>
#include <stdexcept>
#include <vector>

#include "stvd/surface/manifold_sheets.hpp"
#include "stvd/surface/surface_metrics.hpp"
#include "stvd/surface/surface_propagation.hpp"

namespace stvd {
namespace {

/// Triangles from a flat list of corners.
PolygonList triangles(const std::vector<VertexId>& corners) {
  PolygonList faces;
  for (std::size_t i = 0; i + 2 < corners.size(); i += 3) faces.add(corners.begin() + i, corners.begin() + i + 3);
  return faces;
}

TEST(ManifoldSheets, AManifoldMeshComesBackUnchanged) {
  const std::vector<Vec3d> points{{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {1, 1, 0}};
  const PolygonList faces = triangles({0, 1, 2, 1, 3, 2});
  const ManifoldSheets s = splitIntoManifoldSheets(points, faces);
  EXPECT_FALSE(s.changed());
  EXPECT_EQ(s.points.size(), 4u);
  EXPECT_EQ(s.faces.faceVertex, faces.faceVertex);
}

TEST(ManifoldSheets, BowTieVertexGetsACopyPerFan) {
  // Two triangles touching at vertex 0, in the plane: 0-1-2 and 0-3-4.
  const std::vector<Vec3d> points{{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {-1, 0, 0}, {-1, -1, 0}};
  const PolygonList faces = triangles({0, 1, 2, 0, 3, 4});
  EXPECT_THROW(SurfaceDomain(points, faces), SurfaceError);
  const ManifoldSheets s = splitIntoManifoldSheets(points, faces);
  EXPECT_EQ(s.splitVertices, 1u);
  EXPECT_EQ(s.addedVertices, 1u);
  EXPECT_EQ(s.copiesOf(0), (std::vector<VertexId>{0, 5}));
  EXPECT_EQ(s.faces.faceVertex, (std::vector<VertexId>{0, 1, 2, 5, 3, 4}));
  const SurfaceDomain surface(s.points, s.faces);
  const RiemannianMetric metric = isotropicSurfaceMetric(surface);
  int runs = 0;
  const PropagationResult r = propagateOverSheets(surface, metric, s, {1}, {}, &runs);
  EXPECT_EQ(runs, 2);
  // Vertex 4 is reached through the shared vertex: 1 + sqrt(2).
  EXPECT_NEAR(r.distance[4], 1.0 + std::sqrt(2.0), 1e-6);
  EXPECT_EQ(r.distance[0], r.distance[5]);
}

TEST(ManifoldSheets, EdgeOfThreeFacesKeepsTheFirstOppositePairJoined) {
  // Edge 1-2 of three triangles: 0-1-2 (along it 1 -> 2), 1-4-2 standing up
  // (2 -> 1) and 2-1-3 (2 -> 1), in this order. The first pair that runs
  // along it in opposite directions, faces 0 and 1, stays joined; face 2 is
  // cut off, with copies of vertices 1 and 2.
  const std::vector<Vec3d> points{{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {1, 1, 0}, {0.5, 0.5, 1}};
  const PolygonList faces = triangles({0, 1, 2, 1, 4, 2, 2, 1, 3});
  EXPECT_THROW(SurfaceDomain(points, faces), SurfaceError);
  const ManifoldSheets s = splitIntoManifoldSheets(points, faces);
  EXPECT_EQ(s.nonManifoldEdges, 1u);
  EXPECT_EQ(s.detachedFaces, 1u);
  EXPECT_EQ(s.splitVertices, 2u);
  EXPECT_EQ(s.faces.faceVertex, (std::vector<VertexId>{0, 1, 2, 1, 4, 2, 5, 6, 3}));
  const SurfaceDomain surface(s.points, s.faces);
  const RiemannianMetric metric = isotropicSurfaceMetric(surface);
  const PropagationResult r = propagateOverSheets(surface, metric, s, s.copiesOf(0), {});
  // Vertex 3 is reached through an end of the edge (1 + 1), not across its
  // middle (sqrt 2): never shorter than a path on the surface.
  EXPECT_NEAR(r.distance[3], 2.0, 1e-6);
}

TEST(ManifoldSheets, SourceDistancesAreCheckedAndUsed) {
  const std::vector<Vec3d> points{{0, 0, 0}, {1, 0, 0}, {0, 1, 0}};
  const PolygonList faces = triangles({0, 1, 2});
  const SurfaceDomain surface(points, faces);
  const RiemannianMetric metric = isotropicSurfaceMetric(surface);
  PropagationOptions o;
  o.sourceDistances = {-1.0};
  EXPECT_THROW(propagate(surface, metric, {0}, o), std::invalid_argument);
  o.sourceDistances = {1.0, 2.0};
  EXPECT_THROW(propagate(surface, metric, {0}, o), std::invalid_argument);
  o.sourceDistances = {5.0, 0.25};
  const PropagationResult r = propagate(surface, metric, {0, 1}, o);
  EXPECT_EQ(r.distance[1], 0.25);
  EXPECT_NEAR(r.distance[0], 1.25, 1e-6);
  EXPECT_NEAR(r.distance[2], 0.25 + std::sqrt(2.0), 1e-6);
}

}  // namespace
}  // namespace stvd
