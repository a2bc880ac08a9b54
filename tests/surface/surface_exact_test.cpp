// Surfaces against exact polyhedral geodesics on real meshes: CGAL's
// Surface_mesh_shortest_path, run by the test fixture
// (exact_references.cmake and exact_geodesic_oracle.cpp) on meshes of
// CGAL's own data, curved and flat, well and badly shaped, with vertices of
// both curvature signs. STVD_EXACT_DIR names the fixture's folder.
//
// The invariant: every distance is the length of a path on the surface, so
// no method may come out below the exact distance (beyond single-precision
// rounding), at any k. And the segment measure must be worth its time:
// more accurate than Dijkstra and than Lanthier's Steiner points with
// M = 4, and not less accurate as k grows.
#include <gtest/gtest.h>

#include <cstdlib>
#include <fstream>
#include <ostream>
#include <string>
#include <vector>

#include "../core/relative_error.hpp"
#include "stvd/propagation/propagation.hpp"
#include "stvd/lanthier/lanthier_propagation.hpp"
#include "stvd/surface_io/surface_mesh_io.hpp"
#include "stvd/surface/surface_metrics.hpp"
#include "stvd/surface/surface_propagation.hpp"
#include "stvd/surface/surface_lanthier.hpp"

namespace stvd::test {
namespace {

struct RealMesh {
  const char* name;
  const char* what;
  bool curved;
};
void PrintTo(const RealMesh& mesh, std::ostream* out) { *out << mesh.name << " (" << mesh.what << ")"; }

/// The meshes and sources the fixture prepares (tests/surface/CMakeLists.txt).
const RealMesh kMeshes[] = {
    {"armadillo", "curved organic, 26,002 vertices", true},
    {"elephant", "curved organic, well shaped, 2,775 vertices", true},
    {"cheese", "CAD with holes, skinny triangles, mostly saddle vertices", true},
    {"fandisk", "CAD with sharp creases", true},
    {"turbine", "CAD, curved blades", true},
    {"blade", "flat sheet of skinny triangles", false},
};
constexpr VertexId kSources[] = {0, 2000};

std::string fixtureFolder() {
  const char* folder = std::getenv("STVD_EXACT_DIR");
  return folder ? folder : "";
}

/// A mesh of the fixture with its exact distances from one source.
struct Scene {
  SurfaceDomain surface;
  RiemannianMetric metric;
  VertexId source;
  std::vector<double> exact;
};

Scene loadScene(const RealMesh& mesh, VertexId source) {
  const std::string folder = fixtureFolder();
  surface_io::SurfaceMesh m = surface_io::readOff(folder + "/data/meshes/" + mesh.name + ".off");
  SurfaceDomain surface(std::move(m.points), m.faces);
  RiemannianMetric metric = isotropicSurfaceMetric(surface);
  std::vector<double> exact;
  std::ifstream in(folder + "/" + mesh.name + "." + std::to_string(source) + ".txt");
  for (double x; in >> x;) exact.push_back(x);
  EXPECT_EQ(exact.size(), surface.vertexCount()) << mesh.name << ": exact distances missing";
  return Scene{std::move(surface), std::move(metric), source, std::move(exact)};
}

RelativeErrors errorsOf(const Scene& s, const std::vector<double>& distance) {
  RelativeErrors e;
  for (VertexId v = 0; v < s.surface.vertexCount(); ++v)
    if (s.exact[v] > 1e-12) e.add(distance[v], s.exact[v]);
  return e;
}

RelativeErrors stvdErrors(const Scene& s, const std::string& label, int k) {
  PropagationOptions o;  // the defaults: the segment measure
  o.k = k;
  const RelativeErrors e = errorsOf(s, propagate(s.surface, s.metric, {s.source}, o).distance);
  reportMeasurement(label + ", STVD k=" + std::to_string(k), e);
  return e;
}

RelativeErrors dijkstraErrors(const Scene& s, const std::string& label) {
  const RelativeErrors e = errorsOf(s, dijkstra(s.surface, s.metric, {s.source}).distance);
  reportMeasurement(label + ", Dijkstra", e);
  return e;
}

RelativeErrors lanthierErrors(const Scene& s, const std::string& label, int m) {
  LanthierOptions o;
  o.steinerPoints = m;
  const RelativeErrors e = errorsOf(s, lanthierPropagate(s.surface, s.metric, {s.source}, o).distance);
  reportMeasurement(label + ", Lanthier M=" + std::to_string(m), e);
  return e;
}

/// Single-precision lengths summed along a path: at most this far below.
constexpr double kRounding = 1e-5;

class RealMeshAgainstExactGeodesics : public ::testing::TestWithParam<RealMesh> {
 protected:
  void SetUp() override {
    if (fixtureFolder().empty()) GTEST_FAIL() << "STVD_EXACT_DIR is not set (the test fixture sets it)";
  }
};

TEST_P(RealMeshAgainstExactGeodesics, NoMethodAtAnyKGoesBelowTheExactDistance) {
  for (const VertexId source : kSources) {
    const Scene s = loadScene(GetParam(), source);
    const std::string label = std::string(GetParam().name) + " from " + std::to_string(source);
    EXPECT_GT(dijkstraErrors(s, label).minSigned(), -kRounding);
    for (const int k : {2, 4, 8, 12, 16}) {
      const RelativeErrors e = stvdErrors(s, label, k);
      EXPECT_EQ(e.unreached(), 0u);
      EXPECT_GT(e.minSigned(), -kRounding) << label << ", k = " << k;
    }
  }
}

/// More memory can only add real lines to choose from; beyond k = 12 the
/// error stays flat, moving by a few percent of itself where longer chains
/// change the propagation's order (measured: armadillo from 2000, k = 12
/// 0.00090, k = 16 0.00095; fandisk from 2000, 0.00073 and 0.00076).
TEST_P(RealMeshAgainstExactGeodesics, TheErrorDoesNotRiseWithK) {
  for (const VertexId source : kSources) {
    const Scene s = loadScene(GetParam(), source);
    const std::string label = std::string(GetParam().name) + " from " + std::to_string(source);
    double previous = dijkstraErrors(s, label).mean();
    for (const int k : {2, 4, 8, 12, 16}) {
      const double mean = stvdErrors(s, label, k).mean();
      EXPECT_LT(mean, 1.1 * previous) << label << ", k = " << k;
      previous = mean;
    }
  }
}

/// The default (segment measure, k = 8): several times as accurate as
/// Dijkstra on curved meshes, and more accurate than Lanthier M = 4
/// everywhere. Measured: 7.7 times on cheese from vertex 2000 (skinny
/// triangles, 92 % saddle vertices), 8.2 times from vertex 0, 29 to 45 times
/// on armadillo, elephant, fandisk and turbine.
TEST_P(RealMeshAgainstExactGeodesics, TheDefaultBeatsDijkstraAndLanthierWithFourSteinerPoints) {
  for (const VertexId source : kSources) {
    const Scene s = loadScene(GetParam(), source);
    const std::string label = std::string(GetParam().name) + " from " + std::to_string(source);
    const double stvd = stvdErrors(s, label, kDefaultSurfaceMemoryDepth).mean();
    const double dijkstra = dijkstraErrors(s, label).mean();
    const double lanthier = lanthierErrors(s, label, 4).mean();
    if (GetParam().curved) {
      EXPECT_LT(7.5 * stvd, dijkstra) << label;
    }
    EXPECT_LT(stvd, dijkstra) << label;
    EXPECT_LT(stvd, lanthier) << label;
  }
}

INSTANTIATE_TEST_SUITE_P(CgalData, RealMeshAgainstExactGeodesics, ::testing::ValuesIn(kMeshes),
                         [](const ::testing::TestParamInfo<RealMesh>& info) { return std::string(info.param.name); });

/// The curvature metric (anisotropy 10 and 20) against Lanthier M = 16 on
/// the face-wise metric that both measure with: never more than 1 % below
/// it, at least twice as accurate as Dijkstra, and better as k grows.
/// Lanthier's distances are those of paths through Steiner points, longer
/// than the geodesic by what snapping costs; along fandisk's sharp creases,
/// where the metric is strongly anisotropic, M = 16 has not converged: at
/// its worst vertex M = 4, 8, 16 give 0.709, 0.627, 0.602 (anisotropy 10)
/// and the segment measure 0.590, so there the bound is 5 %. A line through
/// vertices along an edge once lost the faces after it (measured 7.9 %
/// below there); that is what fandisk guards.
struct CurvedMesh {
  const char* name;
  double belowLanthier;  // how far below Lanthier M = 16 a vertex may be
};
void PrintTo(const CurvedMesh& mesh, std::ostream* out) { *out << mesh.name; }

class RealMeshUnderTheCurvatureMetric : public ::testing::TestWithParam<CurvedMesh> {};

TEST_P(RealMeshUnderTheCurvatureMetric, StaysAboveLanthierWithSixteenSteinerPointsAndBeatsDijkstra) {
  if (fixtureFolder().empty()) GTEST_FAIL() << "STVD_EXACT_DIR is not set (the test fixture sets it)";
  const char* name = GetParam().name;
  surface_io::SurfaceMesh m = surface_io::readOff(fixtureFolder() + "/data/meshes/" + name + ".off");
  const SurfaceDomain surface(std::move(m.points), m.faces);
  for (const double gamma : {10.0, 20.0}) {
    const RiemannianMetric metric = curvatureMetric(surface, gamma);
    const std::string label = std::string(name) + ", curvature metric " + std::to_string(int(gamma));
    LanthierOptions lanthier;
    lanthier.steinerPoints = 16;
    const Scene s{surface, metric, 0, lanthierPropagate(surface, metric, {0}, lanthier).distance};
    const RelativeErrors d = errorsOf(s, dijkstra(surface, metric, {0}).distance);
    reportMeasurement(label + ", Dijkstra", d);
    double previous = d.mean();
    for (const int k : {4, 8, 16}) {
      const RelativeErrors e = stvdErrors(s, label, k);
      EXPECT_GT(e.minSigned(), -GetParam().belowLanthier) << label << ", k = " << k;
      EXPECT_LT(e.mean(), 1.05 * previous) << label << ", k = " << k;
      if (k == kDefaultSurfaceMemoryDepth) {
        EXPECT_LT(2.0 * e.mean(), d.mean()) << label;
      }
      previous = e.mean();
    }
  }
}

INSTANTIATE_TEST_SUITE_P(CgalData, RealMeshUnderTheCurvatureMetric,
                         ::testing::Values(CurvedMesh{"elephant", 0.01}, CurvedMesh{"cheese", 0.01},
                                           CurvedMesh{"fandisk", 0.05}),
                         [](const ::testing::TestParamInfo<CurvedMesh>& info) { return std::string(info.param.name); });

}  // namespace
}  // namespace stvd::test
