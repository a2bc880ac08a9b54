// Non-manifold meshes, made from a real mesh (CGAL's elephant, 2,775
// vertices) in the four ways scans and CAD exports are non-manifold, split
// into manifold sheets and measured against exact geodesics (CGAL, through
// the fixture's oracle program):
//   * an edge with four faces: the elephant and a copy of it turned about
//     the line of one of its edges, sharing that edge;
//   * a bow-tie vertex: the elephant and its point reflection through one of
//     its vertices, sharing that vertex;
//   * a dangling face: a triangle hanging from one of its edges (three faces);
//   * a pinched boundary: the elephant with a hole (the faces around one
//     vertex removed) and its point reflection through a vertex of the
//     hole's boundary, whose two boundary fans meet there.
// Each is refused by SurfaceDomain as it is; split, it runs, and the exact
// distance on the split surface with its sheets joined at the split
// vertices is known from exact distances on the elephant (the copies are
// isometric): through a shared vertex g, d(x') = d(seed, g) + d(g, x). No
// vertex may come out below it.
#include <gtest/gtest.h>
#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <functional>
#include <string>
#include <vector>

#include "../core/relative_error.hpp"
#include "stvd/propagation/propagation.hpp"
#include "stvd/surface/manifold_sheets.hpp"
#include "stvd/surface/surface_metrics.hpp"
#include "stvd/surface/surface_propagation.hpp"
#include "stvd/surface_io/surface_mesh_io.hpp"

namespace stvd::test {
namespace {

constexpr VertexId kSeed = 0, kShared = 2000, kNeighbour = 41;  // 41: a neighbour of 2000
constexpr double kRounding = 1e-5;

std::string folder() {
  const char* f = std::getenv("STVD_EXACT_DIR");
  return f ? f : "";
}

/// Exact distances on the mesh `name` from `source`: the fixture's file
/// NAME.SOURCE.txt, or computed by the oracle from the OFF file `mesh` (in
/// the fixture's folder) and kept there.
std::vector<double> exactFrom(const std::string& mesh, const std::string& name, VertexId source) {
  const std::string reference = folder() + "/" + name + "." + std::to_string(source) + ".txt";
  if (!std::ifstream(reference)) {
    // Tests run in parallel: each computes into a file of its own, renamed.
    const std::string mine = reference + "." + std::to_string(::getpid());
    const std::string command = std::string("'") + STVD_EXACT_ORACLE + "' '" + folder() + "/" + mesh + "' " +
                                std::to_string(source) + " '" + mine + "'";
    EXPECT_EQ(std::system(command.c_str()), 0) << command;
    std::rename(mine.c_str(), reference.c_str());
  }
  std::vector<double> exact;
  std::ifstream in(reference);
  for (double x; in >> x;) exact.push_back(x);
  return exact;
}

struct Mesh {
  std::vector<Vec3d> points;
  PolygonList faces;
};

Mesh elephant() {
  surface_io::SurfaceMesh m = surface_io::readOff(folder() + "/data/meshes/elephant.off");
  return {m.points, m.faces};
}

/// The elephant without the faces around vertex 2000 (and without that
/// vertex: the vertices after it move down by one), written for the oracle.
Mesh holedElephant() {
  const Mesh m = elephant();
  Mesh h;
  for (VertexId v = 0; v < m.points.size(); ++v)
    if (v != kShared) h.points.push_back(m.points[v]);
  for (std::size_t f = 0; f < m.faces.faceCount(); ++f) {
    std::vector<VertexId> face(m.faces.faceVertex.begin() + m.faces.faceStart[f],
                               m.faces.faceVertex.begin() + m.faces.faceStart[f + 1]);
    bool around = false;
    for (VertexId& v : face) {
      around = around || v == kShared;
      if (v > kShared) --v;
    }
    if (!around) h.faces.add(face.begin(), face.end());
  }
  const std::string path = folder() + "/elephant_holed.off";
  if (!std::ifstream(path)) {
    // Tests run in parallel: each writes its own copy and renames it.
    const std::string part = path + "." + std::to_string(::getpid()) + ".part";
    std::ofstream out(part);
    out.precision(17);
    out << "OFF\n" << h.points.size() << ' ' << h.faces.faceCount() << " 0\n";
    for (const Vec3d& p : h.points) out << p.x << ' ' << p.y << ' ' << p.z << '\n';
    for (std::size_t f = 0; f < h.faces.faceCount(); ++f)
      out << "3 " << h.faces.faceVertex[3 * f] << ' ' << h.faces.faceVertex[3 * f + 1] << ' '
          << h.faces.faceVertex[3 * f + 2] << '\n';
    out.close();
    std::rename(part.c_str(), path.c_str());
  }
  return h;
}

/// `a` and a copy of it moved by `move`, the copy's vertices `shared`
/// replaced by a's (the copy's faces refer to a's; the copy's own ones stay
/// in the list unused, isolated vertices that no distance reaches).
Mesh withCopy(const Mesh& a, const std::function<Vec3d(Vec3d)>& move, const std::vector<VertexId>& shared) {
  Mesh m = a;
  const VertexId n = static_cast<VertexId>(a.points.size());
  for (const Vec3d& p : a.points) m.points.push_back(move(p));
  for (std::size_t f = 0; f < a.faces.faceCount(); ++f) {
    std::vector<VertexId> face;
    for (std::uint32_t c = a.faces.faceStart[f]; c < a.faces.faceStart[f + 1]; ++c) {
      const VertexId v = a.faces.faceVertex[c];
      const bool isShared = std::find(shared.begin(), shared.end(), v) != shared.end();
      face.push_back(isShared ? v : v + n);
    }
    m.faces.add(face.begin(), face.end());
  }
  return m;
}

Vec3d pointReflection(Vec3d p, Vec3d centre) { return 2.0 * centre - p; }

Vec3d rotated(Vec3d p, Vec3d origin, Vec3d axis, double angle) {
  const Vec3d k = (1.0 / norm(axis)) * axis, v = p - origin;
  return origin + std::cos(angle) * v + std::sin(angle) * cross(k, v) + (1.0 - std::cos(angle)) * dot(k, v) * k;
}

struct SheetRun {
  ManifoldSheets sheets;
  std::vector<double> distance;  // per input vertex
  int propagations = 0;
};

SheetRun runFromSeed(const Mesh& m) {
  SheetRun r;
  EXPECT_THROW(SurfaceDomain(m.points, m.faces), SurfaceError) << "the mesh must be non-manifold as built";
  r.sheets = splitIntoManifoldSheets(m.points, m.faces);
  EXPECT_TRUE(r.sheets.changed());
  const SurfaceDomain surface(r.sheets.points, r.sheets.faces);
  const RiemannianMetric metric = isotropicSurfaceMetric(surface);
  const PropagationResult result =
      propagateOverSheets(surface, metric, r.sheets, r.sheets.copiesOf(kSeed), {}, &r.propagations);
  r.distance.assign(result.distance.begin(), result.distance.begin() + m.points.size());
  for (std::size_t v = m.points.size(); v < r.sheets.original.size(); ++v)
    EXPECT_EQ(result.distance[v], result.distance[r.sheets.original[v]]) << "copies of one vertex, one distance";
  return r;
}

/// Every vertex against the exact distance: never below, and close.
void expectExact(const std::string& label, const SheetRun& r, const std::vector<double>& exact, double meanBound) {
  ASSERT_EQ(exact.size(), r.distance.size());
  RelativeErrors e;
  for (std::size_t v = 0; v < exact.size(); ++v)
    if (exact[v] > 1e-12) e.add(r.distance[v], exact[v]);  // < 0: an unused vertex
  reportMeasurement(label, e);
  EXPECT_EQ(e.unreached(), 0u) << label;
  EXPECT_GT(e.minSigned(), -kRounding) << label << ": a distance below the exact one";
  EXPECT_LT(e.mean(), meanBound) << label;
}

class NonManifoldAgainstExactGeodesics : public ::testing::Test {
 protected:
  void SetUp() override {
    if (folder().empty()) GTEST_FAIL() << "STVD_EXACT_DIR is not set (the test fixture sets it)";
  }
};

TEST_F(NonManifoldAgainstExactGeodesics, EdgeWithFourFaces) {
  const Mesh m = elephant();
  const Vec3d a = m.points[kShared], b = m.points[kNeighbour];
  const Mesh book = withCopy(m, [&](Vec3d p) { return rotated(p, a, b - a, 2.0); }, {kShared, kNeighbour});
  const SheetRun r = runFromSeed(book);
  EXPECT_EQ(r.sheets.nonManifoldEdges, 1u);
  EXPECT_EQ(r.sheets.splitVertices, 2u);
  const std::vector<double> fromSeed = exactFrom("data/meshes/elephant.off", "elephant", kSeed);
  const std::vector<double> fromShared = exactFrom("data/meshes/elephant.off", "elephant", kShared);
  const std::vector<double> fromNeighbour = exactFrom("data/meshes/elephant.off", "elephant", kNeighbour);
  std::vector<double> exact(book.points.size());
  const std::size_t n = m.points.size();
  for (std::size_t v = 0; v < n; ++v) {
    exact[v] = fromSeed[v];
    exact[n + v] = std::min(fromSeed[kShared] + fromShared[v], fromSeed[kNeighbour] + fromNeighbour[v]);
  }
  exact[n + kShared] = exact[n + kNeighbour] = -1.0;  // unused
  expectExact("edge with four faces (elephant + a copy turned about edge 2000-41)", r, exact, 0.002);
}

TEST_F(NonManifoldAgainstExactGeodesics, BowTieVertex) {
  const Mesh m = elephant();
  const Vec3d centre = m.points[kShared];
  const Mesh bowTie = withCopy(m, [&](Vec3d p) { return pointReflection(p, centre); }, {kShared});
  const SheetRun r = runFromSeed(bowTie);
  EXPECT_EQ(r.sheets.nonManifoldEdges, 0u);
  EXPECT_EQ(r.sheets.splitVertices, 1u);
  const std::vector<double> fromSeed = exactFrom("data/meshes/elephant.off", "elephant", kSeed);
  const std::vector<double> fromShared = exactFrom("data/meshes/elephant.off", "elephant", kShared);
  const std::size_t n = m.points.size();
  std::vector<double> exact(2 * n);
  for (std::size_t v = 0; v < n; ++v) {
    exact[v] = fromSeed[v];
    exact[n + v] = fromSeed[kShared] + fromShared[v];
  }
  exact[n + kShared] = -1.0;  // unused
  expectExact("bow-tie vertex (elephant + its reflection through vertex 2000)", r, exact, 0.002);
}

TEST_F(NonManifoldAgainstExactGeodesics, DanglingFace) {
  Mesh m = elephant();
  const Vec3d a = m.points[kShared], b = m.points[kNeighbour];
  // A triangle standing off the edge: its far corner off the surface.
  const Vec3d up = cross(b - a, Vec3d{0.3, 0.9, 0.2});
  m.points.push_back(0.5 * (a + b) + (norm(b - a) / norm(up)) * up);
  const VertexId p = static_cast<VertexId>(m.points.size() - 1);
  m.faces.add({kShared, kNeighbour, p});
  const SheetRun r = runFromSeed(m);
  EXPECT_EQ(r.sheets.nonManifoldEdges, 1u);
  EXPECT_EQ(r.sheets.detachedFaces, 1u);
  const std::vector<double> fromSeed = exactFrom("data/meshes/elephant.off", "elephant", kSeed);
  std::vector<double> exact(fromSeed);
  exact.push_back(std::min(fromSeed[kShared] + norm(m.points[p] - a), fromSeed[kNeighbour] + norm(m.points[p] - b)));
  expectExact("dangling face (a triangle on edge 2000-41)", r, exact, 0.002);
}

TEST_F(NonManifoldAgainstExactGeodesics, PinchedBoundary) {
  const Mesh h = holedElephant();
  const VertexId rim = kNeighbour;  // on the hole's boundary (41 < 2000 keeps its number)
  const Vec3d centre = h.points[rim];
  const Mesh pinched = withCopy(h, [&](Vec3d p) { return pointReflection(p, centre); }, {rim});
  const SheetRun r = runFromSeed(pinched);
  EXPECT_EQ(r.sheets.splitVertices, 1u);
  const std::vector<double> fromSeed = exactFrom("elephant_holed.off", "elephant_holed", kSeed);
  const std::vector<double> fromRim = exactFrom("elephant_holed.off", "elephant_holed", rim);
  const std::size_t n = h.points.size();
  std::vector<double> exact(2 * n);
  for (std::size_t v = 0; v < n; ++v) {
    exact[v] = fromSeed[v];
    exact[n + v] = fromSeed[rim] + fromRim[v];
  }
  exact[n + rim] = -1.0;  // unused
  expectExact("pinched boundary (holed elephant + its reflection through rim vertex 41)", r, exact, 0.002);
}

}  // namespace
}  // namespace stvd::test
