// Steiner-point propagation on tetrahedral meshes, and the cell structure
// it runs on. The mesh is a box of cubes each split into Kuhn's six
// tetrahedra, with jittered interior vertices, under a constant anisotropic
// metric: the box is convex, so the exact distance is the norm of the
// displacement and no Steiner distance may fall below it.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>
#include <vector>

#include "exact_metrics.hpp"
#include "relative_error.hpp"
#include "scenes.hpp"
#include "stvd/lanthier/lanthier_propagation.hpp"
#include "stvd/cell_mesh/tetrahedral_cells.hpp"
#include "stvd/cell_mesh/cell_mesh_lanthier.hpp"

namespace stvd {
namespace {

using test::RelativeErrors;

constexpr double kFloatSlack = 1e-5;

TEST(TetrahedralCells, OneKuhnCubeHasItsEdgesFacesAndIncidences) {
  const test::TetrahedralBox box = test::kuhnTetrahedralBox({1, 1, 1}, {1, 1, 1}, 0.0, 1);
  const TetrahedralCells cells(box.points, box.tets);
  EXPECT_EQ(cells.vertexCount(), 8u);
  // 12 cube edges, 6 face diagonals, the main diagonal.
  EXPECT_EQ(cells.edges().size(), 19u);
  // 12 boundary triangles (2 per cube face) and 6 inside.
  EXPECT_EQ(cells.faces().size(), 18u);
  std::size_t boundary = 0, inner = 0;
  for (std::uint32_t f = 0; f < cells.faces().size(); ++f) {
    const auto n = cells.faceTetsEnd(f) - cells.faceTetsBegin(f);
    boundary += n == 1 ? 1 : 0;
    inner += n == 2 ? 1 : 0;
  }
  EXPECT_EQ(boundary, 12u);
  EXPECT_EQ(inner, 6u);
  // The main diagonal (0,0,0)-(1,1,1) is in all six tetrahedra, both its
  // end points too; a cube edge is in one or two.
  const VertexId origin = box.id(0, 0, 0), opposite = box.id(1, 1, 1);
  EXPECT_EQ(cells.vertexTetsEnd(origin) - cells.vertexTetsBegin(origin), 6);
  EXPECT_EQ(cells.vertexTetsEnd(opposite) - cells.vertexTetsBegin(opposite), 6);
  std::size_t incidences = 0;
  for (std::uint32_t e = 0; e < cells.edges().size(); ++e) {
    const auto n = cells.edgeTetsEnd(e) - cells.edgeTetsBegin(e);
    incidences += n;
    if (cells.edges()[e] == TetrahedralCells::Edge{origin, opposite}) {
      EXPECT_EQ(n, 6);
    }
  }
  EXPECT_EQ(incidences, 36u);
  // Each tetrahedron's edge and face lists name its own edges and faces.
  for (std::size_t t = 0; t < cells.tets().size(); ++t) {
    const auto& tet = cells.tets()[t];
    const auto& e01 = cells.edges()[cells.tetEdges(t)[0]];
    EXPECT_EQ(e01, (TetrahedralCells::Edge{std::min(tet[0], tet[1]), std::max(tet[0], tet[1])}));
    for (int f = 0; f < 4; ++f)
      for (const VertexId v : cells.faces()[cells.tetFaces(t)[f]]) EXPECT_NE(v, tet[f]);
  }
}

TEST(TetrahedralCells, RejectsBrokenTetrahedra) {
  const std::vector<Vec3d> points{{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1}, {1, 1, 1}};
  EXPECT_THROW(TetrahedralCells(points, {}), std::invalid_argument);
  EXPECT_THROW(TetrahedralCells(points, {{0, 1, 2, 5}}), std::invalid_argument);
  EXPECT_THROW(TetrahedralCells(points, {{0, 1, 2, 1}}), std::invalid_argument);
  // Three tetrahedra on the face (0, 1, 2).
  EXPECT_THROW(TetrahedralCells(points, {{0, 1, 2, 3}, {0, 1, 2, 4}, {2, 1, 0, 3}}), std::invalid_argument);
}

struct TetScene {
  test::TetrahedralBox box = test::kuhnTetrahedralBox({8, 8, 8}, {1.0, 1.25, 1.5}, 0.2, 7);
  TetrahedralCells cells{box.points, box.tets};
  test::Mat3 tensor = test::uniaxialTensor(4.0, {0.5, -0.3, 0.8});
  RiemannianMetric metric = RiemannianMetric::constant(cells.vertexCount(), test::toSymTensor(tensor));
  VertexId source = box.id(4, 3, 4);

  double exact(Vec3d p) const { return test::tensorNorm(tensor, p - box.points[source]); }
};

const TetScene& tetScene() {
  static const TetScene scene;
  return scene;
}

// Measured relative errors over the 728 other vertices (Release, x86-64),
// M = 1, 2, 4, 8: mean 0.0502, 0.0337, 0.0156, 0.00602 (max 0.472, 0.374,
// 0.175, 0.0647). Bounds about 1.4 times the M = 8 figures.
constexpr double kTetMeanBoundM8 = 0.0085;
constexpr double kTetMaxBoundM8 = 0.09;

TEST(SteinerTetrahedra, ConstantMetricErrorFallsWithEveryDoublingOfSteinerPoints) {
  const TetScene& scene = tetScene();
  double previous = std::numeric_limits<double>::infinity();
  for (int m : {1, 2, 4, 8}) {
    LanthierOptions o;
    o.steinerPoints = m;
    const LanthierResult r = lanthierPropagate(scene.cells, scene.metric, {scene.source}, o);
    EXPECT_EQ(r.termination, Termination::Completed);
    RelativeErrors e;
    for (VertexId v = 0; v < scene.cells.vertexCount(); ++v)
      if (v != scene.source) e.add(r.distance[v], scene.exact(scene.box.points[v]));
    test::reportMeasurement("Steiner tetrahedra gamma 4, M = " + std::to_string(m), e);
    EXPECT_EQ(e.unreached(), 0u);
    EXPECT_LT(e.mean(), previous) << "M = " << m;
    EXPECT_GE(e.minSigned(), -kFloatSlack) << "M = " << m;
    previous = e.mean();
    if (m == 8) {
      EXPECT_LE(e.mean(), kTetMeanBoundM8);
      EXPECT_LE(e.max(), kTetMaxBoundM8);
    }
  }
}

TEST(SteinerTetrahedra, SteinerPointFieldHoldsTheDistanceAtEachPointsPosition) {
  const TetScene& scene = tetScene();
  const int m = 3;
  LanthierOptions o;
  o.steinerPoints = m;
  o.keepPointDistances = true;
  const LanthierResult r = lanthierPropagate(scene.cells, scene.metric, {scene.source}, o);
  ASSERT_EQ(r.graphPoints, scene.cells.vertexCount() + 3 * scene.cells.edges().size() +
                               3 * scene.cells.faces().size());
  RelativeErrors e;
  for (SteinerPointId p = 0; p < r.graphPoints; ++p) {
    const Vec3d x = steinerPointPosition(scene.cells, m, p);
    if (p < scene.cells.vertexCount()) {
      ASSERT_EQ(r.pointDistance[p], r.distance[p]);
      if (p == scene.source) continue;
    }
    e.add(r.pointDistance[p], scene.exact(x));
  }
  test::reportMeasurement("Steiner tetrahedra gamma 4, M = 3, all points", e);
  EXPECT_EQ(e.unreached(), 0u);
  EXPECT_GE(e.minSigned(), -kFloatSlack);
  // Measured: mean 0.0280 over the 32,864 points.
  EXPECT_LE(e.mean(), 0.039);
  // The third point on an edge sits 3/4 of the way along it.
  const auto& edge = scene.cells.edges()[5];
  const Vec3d third = steinerPointPosition(scene.cells, m, scene.cells.vertexCount() + 5 * 3 + 2);
  EXPECT_LT(norm(third - (0.25 * scene.box.points[edge[0]] + 0.75 * scene.box.points[edge[1]])), 1e-12);
}

}  // namespace
}  // namespace stvd
