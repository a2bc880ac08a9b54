// The tetrahedra a CellMeshDomain keeps (TetrahedralRegion): neighbours
// across faces, the places where the mesh is not convex and how far each
// vertex lies from them, and the walk of a straight segment through the
// tetrahedra, checked against where the segment runs as worked out from the
// shape of the mesh. Kuhn boxes put vertices exactly on lattice lines, so
// segments run along edges and faces and through vertices.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <stdexcept>
#include <vector>

#include "scenes.hpp"
#include "stvd/cell_mesh/cell_mesh_domain.hpp"

namespace stvd {
namespace {

/// The pieces of one walk, and whether it reached the end.
struct Walk {
  bool inside = false;
  std::vector<SegmentPiece> pieces;
};

Walk walk(const CellMeshDomain& mesh, VertexId from, VertexId to, int maxSteps = 1000) {
  Walk w;
  w.inside = mesh.tetrahedra()->walk(mesh.points().data(), from, to, maxSteps,
                                     [&](const SegmentPiece& p) { w.pieces.push_back(p); });
  return w;
}

/// The pieces tile [0, 1] in order, and at each piece's ends the
/// barycentric coordinates are those of the segment's point there, in the
/// tetrahedron (within the walk's tolerance).
void expectPiecesFollowTheSegment(const CellMeshDomain& mesh, VertexId from, VertexId to, const Walk& w) {
  ASSERT_TRUE(w.inside);
  ASSERT_FALSE(w.pieces.empty());
  EXPECT_EQ(w.pieces.front().s0, 0.0);
  EXPECT_EQ(w.pieces.back().s1, 1.0);
  const Vec3d a = mesh.physicalPoint(from), b = mesh.physicalPoint(to);
  for (std::size_t n = 0; n < w.pieces.size(); ++n) {
    const SegmentPiece& p = w.pieces[n];
    EXPECT_LT(p.s0, p.s1);
    if (n > 0) {
      EXPECT_EQ(p.s0, w.pieces[n - 1].s1);
    }
    const auto& corners = mesh.tetrahedra()->corners(p.tetrahedron);
    for (const double s : {p.s0, 0.5 * (p.s0 + p.s1), p.s1}) {
      Vec3d x{};
      double sum = 0.0;
      for (int c = 0; c < 4; ++c) {
        const double l = p.start[c] + s * p.slope[c];
        EXPECT_GE(l, -1e-8) << "piece " << n << " at s = " << s;
        sum += l;
        x = x + l * mesh.physicalPoint(corners[c]);
      }
      EXPECT_NEAR(sum, 1.0, 1e-9);
      EXPECT_LT(norm(x - (a + s * (b - a))), 1e-9 * (1.0 + norm(b - a)));
    }
  }
}

TEST(TetrahedralRegion, FaceNeighboursShareAFaceAndPointBack) {
  const test::TetrahedralBox box = test::kuhnTetrahedralBox({4, 3, 2}, {1.0, 1.2, 0.9}, 0.2, 5);
  const CellMeshDomain mesh = CellMeshDomain::fromTetrahedra(box.points, box.tets);
  const TetrahedralRegion& region = *mesh.tetrahedra();
  ASSERT_EQ(region.tetrahedronCount(), box.tets.size());
  std::size_t boundaryFaces = 0;
  for (std::uint32_t t = 0; t < region.tetrahedronCount(); ++t) {
    const auto& c = region.corners(t);
    for (int f = 0; f < 4; ++f) {
      const std::uint32_t u = region.neighbor(t, f);
      if (u == TetrahedralRegion::kNoTetrahedron) {
        ++boundaryFaces;
        continue;
      }
      const auto& d = region.corners(u);
      int shared = 0, opposite = -1;
      for (int g = 0; g < 4; ++g) {
        const bool inT = std::find(c.begin(), c.end(), d[g]) != c.end();
        shared += inT ? 1 : 0;
        if (!inT) opposite = g;
      }
      EXPECT_EQ(shared, 3);
      EXPECT_EQ(std::find(d.begin(), d.end(), c[f]), d.end()) << "the face opposite corner f is the shared one";
      ASSERT_GE(opposite, 0);
      EXPECT_EQ(region.neighbor(u, opposite), t);
    }
  }
  // Two triangles per boundary square of the 4 x 3 x 2 box.
  EXPECT_EQ(boundaryFaces, 2u * 2u * (4 * 3 + 3 * 2 + 4 * 2));
  for (VertexId v = 0; v < mesh.vertexCount(); ++v) {
    std::size_t having = 0;
    for (std::uint32_t t = 0; t < region.tetrahedronCount(); ++t) {
      const auto& c = region.corners(t);
      having += std::find(c.begin(), c.end(), v) != c.end() ? 1 : 0;
    }
    ASSERT_EQ(static_cast<std::size_t>(region.tetrahedraAroundEnd(v) - region.tetrahedraAroundBegin(v)), having);
    for (const std::uint32_t* t = region.tetrahedraAroundBegin(v); t != region.tetrahedraAroundEnd(v); ++t) {
      const auto& c = region.corners(*t);
      EXPECT_NE(std::find(c.begin(), c.end(), v), c.end());
    }
  }
}

TEST(TetrahedralRegion, AFaceOfThreeTetrahedraIsRefused) {
  const std::vector<Vec3d> points{{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1}, {0, 0, -1}, {1, 1, 1}};
  EXPECT_NO_THROW(CellMeshDomain::fromTetrahedra(points, {{0, 1, 2, 3}, {0, 1, 2, 4}}));
  try {
    CellMeshDomain::fromTetrahedra(points, {{0, 1, 2, 3}, {0, 1, 2, 4}, {2, 1, 0, 5}});
    FAIL() << "a face of three tetrahedra was accepted";
  } catch (const std::invalid_argument& e) {
    EXPECT_EQ(std::string(e.what()),
              "the face with corners at (0, 0, 0), (0, 1, 0), (1, 0, 0) belongs to more than two tetrahedra");
  }
}

TEST(TetrahedralRegion, MeshesOfOtherCellsHaveNone) {
  const std::vector<Vec3d> points{{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1}};
  EXPECT_EQ(CellMeshDomain::fromEdges(points, {{0, 1}, {1, 2}}).tetrahedra(), nullptr);
  EXPECT_EQ(CellMeshDomain::fromPolyhedra(points, {{{0, 1, 2}, {0, 1, 3}, {1, 2, 3}, {2, 0, 3}}}).tetrahedra(), nullptr);
}

TEST(TetrahedralRegion, ABoxIsConvexEverywhere) {
  const test::TetrahedralBox box = test::kuhnTetrahedralBox({6, 5, 4}, {1.0, 1.2, 1.5}, 0.15, 3);
  const CellMeshDomain mesh = CellMeshDomain::fromTetrahedra(box.points, box.tets);
  const TetrahedralRegion& region = *mesh.tetrahedra();
  EXPECT_EQ(region.nonConvexEdgeCount(), 0u);
  EXPECT_EQ(region.nonConvexVertexCount(), 0u);
  for (VertexId v = 0; v < mesh.vertexCount(); ++v) {
    EXPECT_EQ(region.clearance(v), std::numeric_limits<float>::infinity());
    EXPECT_EQ(region.convexReach(v), std::numeric_limits<float>::infinity());
  }
}

/// The L-shaped prism of 16 x 16 x 4 cubes (its notch is the line x = y = 8)
/// and the segments that leave it.
struct LShape {
  test::LShapedPrism prism{8, 4};
  CellMeshDomain mesh = CellMeshDomain::fromTetrahedra(prism.box.points, prism.tets);

  bool used(VertexId v) const { return prism.contains(mesh.physicalPoint(v)); }
  /// Whether the segment a -> b passes through the open quadrant x > 8,
  /// y > 8, in exact integer arithmetic (the corners lie on the lattice):
  /// the parameters t in (0, 1) with x(t) > 8 and with y(t) > 8 are open
  /// intervals, and the segment leaves the L when they overlap.
  bool leaves(VertexId a, VertexId b) const {
    const Vec3d p = mesh.physicalPoint(a), q = mesh.physicalPoint(b);
    // t in (low, high) as fractions num / den with den > 0.
    struct Fraction {
      long long num, den;
    };
    auto less = [](Fraction x, Fraction y) { return x.num * y.den < y.num * x.den; };
    Fraction low{0, 1}, high{1, 1};
    for (const auto& [from, to] : {std::pair<double, double>{p.x, q.x}, std::pair<double, double>{p.y, q.y}}) {
      const long long f = std::llround(from), d = std::llround(to) - f;
      if (d == 0) {
        if (f <= 8) return false;
      } else if (d > 0) {
        const Fraction t{8 - f, d};  // x(t) > 8 for t > t0
        if (less(low, t)) low = t;
      } else {
        const Fraction t{f - 8, -d};  // x(t) > 8 for t < t0
        if (less(t, high)) high = t;
      }
    }
    return less(low, high);
  }
};

TEST(TetrahedralRegion, TheNotchOfAnLShapedMeshIsItsOnlyNonConvexPlace) {
  const LShape l;
  const TetrahedralRegion& region = *l.mesh.tetrahedra();
  // The notch line x = y = 8, 0 <= z <= 4, is four lattice edges.
  EXPECT_EQ(region.nonConvexEdgeCount(), 4u);
  EXPECT_EQ(region.nonConvexVertexCount(), 0u);
  for (VertexId v = 0; v < l.mesh.vertexCount(); ++v) {
    if (!l.used(v)) continue;
    const Vec3d p = l.mesh.physicalPoint(v);
    const double toNotch = std::hypot(p.x - 8.0, p.y - 8.0);  // the notch spans the prism's height
    ASSERT_LE(region.clearance(v), toNotch) << "vertex " << v;
    // A lower bound, but not a loose one: the distance transform's cells are
    // under a millimetre wide here.
    EXPECT_GE(region.clearance(v), toNotch - 3.0) << "vertex " << v;
    EXPECT_TRUE(region.convexReach(v) == 0.f || region.convexReach(v) == region.clearance(v));
    if (toNotch > 5.0) {
      EXPECT_GT(region.convexReach(v), 0.f);
    }
  }
}

TEST(TetrahedralRegion, PartsTouchingAtAVertexOrAlongAnEdgeAreNotConvexThere) {
  const test::TetrahedralBox cubes = test::kuhnTetrahedralBox({2, 2, 2}, {1.0, 1.0, 1.0}, 0.0, 1);
  const CellMeshDomain atVertex = CellMeshDomain::fromTetrahedra(
      cubes.points, cubes.tetrahedraOfCubes([](int i, int j, int k) { return i == j && j == k; }));
  EXPECT_EQ(atVertex.tetrahedra()->nonConvexVertexCount(), 1u);
  EXPECT_EQ(atVertex.tetrahedra()->clearance(cubes.id(1, 1, 1)), 0.f);
  EXPECT_FALSE(walk(atVertex, cubes.id(0, 1, 1), cubes.id(1, 2, 1)).inside);
  EXPECT_TRUE(walk(atVertex, cubes.id(0, 0, 0), cubes.id(2, 2, 2)).inside) << "through the touching vertex";

  const CellMeshDomain alongEdge = CellMeshDomain::fromTetrahedra(
      cubes.points, cubes.tetrahedraOfCubes([](int i, int j, int k) { return k == 0 && i == j; }));
  EXPECT_GE(alongEdge.tetrahedra()->nonConvexEdgeCount(), 1u);
  EXPECT_EQ(alongEdge.tetrahedra()->clearance(cubes.id(1, 1, 0)), 0.f);
  EXPECT_FALSE(walk(alongEdge, cubes.id(0, 1, 0), cubes.id(1, 2, 0)).inside);
  EXPECT_TRUE(walk(alongEdge, cubes.id(0, 0, 0), cubes.id(2, 2, 1)).inside) << "through the shared edge";
}

TEST(TetrahedralRegion, WalksAlongEdgesAndFacesAndThroughVertices) {
  const test::TetrahedralBox box = test::kuhnTetrahedralBox({6, 5, 4}, {1.0, 1.0, 1.0}, 0.0, 1);
  const CellMeshDomain mesh = CellMeshDomain::fromTetrahedra(box.points, box.tets);
  // Along lattice lines through vertices, face and body diagonals (mesh
  // edges in a Kuhn box, or not), along the boundary, and corner to corner.
  const std::vector<std::pair<VertexId, VertexId>> lines{
      {box.id(0, 2, 2), box.id(6, 2, 2)}, {box.id(3, 0, 1), box.id(3, 5, 1)}, {box.id(1, 1, 0), box.id(1, 1, 4)},
      {box.id(0, 0, 0), box.id(4, 4, 4)}, {box.id(4, 4, 4), box.id(0, 0, 0)}, {box.id(0, 0, 2), box.id(5, 5, 2)},
      {box.id(6, 0, 0), box.id(2, 4, 4)}, {box.id(0, 0, 0), box.id(6, 5, 4)}, {box.id(0, 0, 0), box.id(6, 0, 0)},
      {box.id(0, 5, 4), box.id(6, 5, 4)}, {box.id(0, 0, 4), box.id(6, 5, 4)}, {box.id(2, 1, 1), box.id(3, 2, 1)}};
  for (const auto& [a, b] : lines) {
    SCOPED_TRACE(::testing::Message() << "from " << a << " to " << b);
    expectPiecesFollowTheSegment(mesh, a, b, walk(mesh, a, b));
  }
  // And between random pairs of vertices.
  test::Random random(11);
  for (int n = 0; n < 400; ++n) {
    const auto a = static_cast<VertexId>(random.next() % mesh.vertexCount());
    const auto b = static_cast<VertexId>(random.next() % mesh.vertexCount());
    if (a == b) continue;
    SCOPED_TRACE(::testing::Message() << "from " << a << " to " << b);
    expectPiecesFollowTheSegment(mesh, a, b, walk(mesh, a, b));
  }
}

TEST(TetrahedralRegion, AWalkIsRefusedExactlyWhereTheSegmentLeavesAnLShapedMesh) {
  const LShape l;
  std::vector<VertexId> used;
  for (VertexId v = 0; v < l.mesh.vertexCount(); ++v)
    if (l.used(v)) used.push_back(v);
  test::Random random(23);
  std::size_t refused = 0, touching = 0;
  for (int n = 0; n < 3000; ++n) {
    const VertexId a = used[random.next() % used.size()], b = used[random.next() % used.size()];
    if (a == b) continue;
    const bool leaves = l.leaves(a, b);
    SCOPED_TRACE(::testing::Message() << "from " << a << " to " << b);
    const Walk w = walk(l.mesh, a, b);
    EXPECT_EQ(w.inside, !leaves);
    if (w.inside) expectPiecesFollowTheSegment(l.mesh, a, b, w);
    refused += leaves ? 1 : 0;
  }
  // Segments that only touch the notch (through the line x = y = 8) or run
  // along the notch's faces stay in the mesh.
  for (int z = 0; z <= 4; ++z) {
    const test::TetrahedralBox& box = l.prism.box;
    for (const auto& [a, b] : std::vector<std::pair<VertexId, VertexId>>{
             {box.id(6, 10, z), box.id(10, 6, 4 - z)}, {box.id(8, 16, z), box.id(8, 0, 4 - z)},
             {box.id(16, 8, z), box.id(0, 8, z)}, {box.id(8, 8, 0), box.id(8, 8, 4)}}) {
      ASSERT_FALSE(l.leaves(a, b));
      const Walk w = walk(l.mesh, a, b);
      EXPECT_TRUE(w.inside) << "from " << a << " to " << b;
      if (w.inside) expectPiecesFollowTheSegment(l.mesh, a, b, w);
      ++touching;
    }
  }
  EXPECT_GT(refused, 300u);
  EXPECT_EQ(touching, 20u);
}

TEST(TetrahedralRegion, AWalkThroughACavityIsRefused) {
  // An 8^3 box without the 2 x 2 x 2 cubes around its centre (4, 4, 4).
  const test::TetrahedralBox box = test::kuhnTetrahedralBox({8, 8, 8}, {1.0, 1.0, 1.0}, 0.0, 1);
  const CellMeshDomain mesh = CellMeshDomain::fromTetrahedra(box.points, box.tetrahedraOfCubes([](int i, int j, int k) {
    return !(i >= 3 && i < 5 && j >= 3 && j < 5 && k >= 3 && k < 5);
  }));
  // The cavity's twelve cube edges, two lattice edges each, are reflex seen
  // from the mesh; its face diagonals are flat.
  EXPECT_EQ(mesh.tetrahedra()->nonConvexEdgeCount(), 24u);
  EXPECT_FALSE(walk(mesh, box.id(1, 4, 4), box.id(7, 4, 4)).inside);
  EXPECT_FALSE(walk(mesh, box.id(2, 2, 2), box.id(6, 6, 6)).inside);
  EXPECT_TRUE(walk(mesh, box.id(1, 3, 4), box.id(7, 3, 4)).inside) << "along the cavity's wall";
  EXPECT_TRUE(walk(mesh, box.id(1, 2, 4), box.id(7, 2, 4)).inside);
  EXPECT_EQ(mesh.tetrahedra()->clearance(box.id(3, 3, 3)), 0.f);
  EXPECT_GT(mesh.tetrahedra()->clearance(box.id(0, 0, 0)), 1.5f);
}

TEST(TetrahedralRegion, AWalkNeedingMoreStepsThanAllowedIsRefused) {
  const test::TetrahedralBox box = test::kuhnTetrahedralBox({8, 3, 3}, {1.0, 1.0, 1.0}, 0.1, 2);
  const CellMeshDomain mesh = CellMeshDomain::fromTetrahedra(box.points, box.tets);
  const VertexId a = box.id(0, 1, 1), b = box.id(8, 2, 2);
  const Walk all = walk(mesh, a, b);
  ASSERT_TRUE(all.inside);
  ASSERT_GT(all.pieces.size(), 8u);
  EXPECT_TRUE(walk(mesh, a, b, static_cast<int>(all.pieces.size())).inside);
  EXPECT_FALSE(walk(mesh, a, b, static_cast<int>(all.pieces.size()) - 1).inside);
}

}  // namespace
}  // namespace stvd
