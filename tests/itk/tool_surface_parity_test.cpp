// Surfaces on a par with volumes on the command line: one help text for
// every kind of input, --seed-point (nearest vertex or an inserted point),
// --max-distance and --stats for surfaces, STL input, and PLY output that
// keeps the input's coordinates exactly.
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <fstream>
#include <sstream>

#include "../surface/surface_meshes.hpp"
#include "test_support.hpp"

namespace stvd::testing {
namespace {

using stvd::test::GeneratedSurface;

/// The distance column of a .csv written by the tool ("inf" = unreached).
std::vector<double> readDistances(const std::string& path) {
  std::ifstream in(path);
  std::string line;
  std::getline(in, line);
  std::vector<double> d;
  while (std::getline(in, line)) {
    const std::string value = line.substr(line.find(',') + 1);
    d.push_back(value == "inf" ? INFINITY : std::stod(value));
  }
  return d;
}

/// The triangles of a surface as an ASCII or binary STL (three corners per facet).
void writeStl(const std::string& path, const GeneratedSurface& s, bool binary) {
  std::ofstream out(path, std::ios::binary);
  const std::size_t n = s.faces.faceCount();
  if (binary) {
    out << std::string(80, ' ');
    const std::uint32_t count = static_cast<std::uint32_t>(n);
    out.write(reinterpret_cast<const char*>(&count), 4);
  } else {
    out << "solid generated\n";
    out.precision(9);
  }
  for (std::size_t f = 0; f < n; ++f) {
    const std::uint32_t b = s.faces.faceStart[f];
    if (binary) {
      float values[12] = {0, 0, 1};
      for (int c = 0; c < 3; ++c) {
        const Vec3d& p = s.points[s.faces.faceVertex[b + c]];
        values[3 + 3 * c] = float(p.x), values[4 + 3 * c] = float(p.y), values[5 + 3 * c] = float(p.z);
      }
      out.write(reinterpret_cast<const char*>(values), 48);
      out.write("\0\0", 2);
    } else {
      out << "facet normal 0 0 1\n outer loop\n";
      for (int c = 0; c < 3; ++c) {
        const Vec3d& p = s.points[s.faces.faceVertex[b + c]];
        out << "  vertex " << float(p.x) << ' ' << float(p.y) << ' ' << float(p.z) << '\n';
      }
      out << " endloop\nendfacet\n";
    }
  }
  if (!binary) out << "endsolid generated\n";
}

void writeOff(const std::string& path, const GeneratedSurface& s) {
  std::ofstream out(path);
  out.precision(17);
  out << "OFF\n" << s.points.size() << ' ' << s.faces.faceCount() << " 0\n";
  for (const Vec3d& p : s.points) out << p.x << ' ' << p.y << ' ' << p.z << '\n';
  for (std::size_t f = 0; f < s.faces.faceCount(); ++f) {
    out << s.faces.faceStart[f + 1] - s.faces.faceStart[f];
    for (std::uint32_t c = s.faces.faceStart[f]; c < s.faces.faceStart[f + 1]; ++c) out << ' ' << s.faces.faceVertex[c];
    out << '\n';
  }
}

class ToolSurfaceParity : public ScratchFolderTest {};

TEST(ToolDistanceHelp, ListsSurfaceAndTetMeshOptionsInSectionsOfTheirOwn) {
  const ToolRun run = runTool({"help", "distance"});
  ASSERT_EQ(run.exitCode, 0) << run.err;
  const std::size_t surfaces = run.out.find("=== Polygon surfaces");
  const std::size_t tets = run.out.find("=== Tetrahedral meshes");
  ASSERT_NE(surfaces, std::string::npos) << run.out;
  ASSERT_NE(tets, std::string::npos) << run.out;
  const std::string surfaceSection = run.out.substr(surfaces, tets - surfaces);
  for (const std::string option : {"--seed-vertex", "--seed-point", "--seed-at", "--metric", "--anisotropy",
                                   "--max-distance", "--stats", "stl"})
    EXPECT_NE(surfaceSection.find(option), std::string::npos) << option;
  for (const std::string option : {"--tensors", "--reference", "--outside-image"})
    EXPECT_NE(run.out.find(option, tets), std::string::npos) << option;
}

TEST_F(ToolSurfaceParity, StlInAsciiAndBinaryGivesTheDistancesOfTheSameMeshWelded) {
  const GeneratedSurface s = test::planeMesh(12, 12, 6.0, 6.0, 0.5, 0.3, false, 5);
  writeOff(path("plane.off"), s);
  writeStl(path("ascii.stl"), s, false);
  writeStl(path("binary.stl"), s, true);
  std::vector<std::vector<double>> results;
  for (const std::string name : {"plane.off", "ascii.stl", "binary.stl"}) {
    // Dijkstra: its distances do not depend on the vertex numbering, which
    // welding changes (STVD's 1-ring frames and ties do).
    const ToolRun run = runTool(
        {"distance", path(name), "--seed-point", "0,0,0", "--method", "dijkstra", "-o", path(name + ".csv")});
    ASSERT_EQ(run.exitCode, 0) << name << ": " << run.err;
    if (name != "plane.off") {
      // 3 corners per triangle, 169 vertices: the rest are welded.
      const std::string welded = std::to_string(3 * s.faces.faceCount() - s.points.size());
      EXPECT_NE(run.out.find("169 vertices (" + welded + " duplicate facet corners welded)"), std::string::npos)
          << run.out;
    }
    results.push_back(readDistances(path(name + ".csv")));
  }
  // Welding numbers the vertices in the order their corners first appear.
  std::vector<VertexId> fileVertexOf;
  std::vector<bool> seen(s.points.size(), false);
  for (const VertexId v : s.faces.faceVertex)
    if (!seen[v]) {
      seen[v] = true;
      fileVertexOf.push_back(v);
    }
  // STL holds float coordinates: the same distances to float precision.
  ASSERT_EQ(results[1].size(), s.points.size());
  for (std::size_t v = 0; v < s.points.size(); ++v) {
    EXPECT_NEAR(results[1][v], results[0][fileVertexOf[v]], 1e-5) << v;
    EXPECT_NEAR(results[2][v], results[0][fileVertexOf[v]], 1e-5) << v;
  }
}

TEST_F(ToolSurfaceParity, ASeedPointIsItsNearestVertexOrThePointItself) {
  const GeneratedSurface s = test::planeMesh(40, 40, 10.0, 10.0, 0.5, 0.3, false, 7);
  writeOff(path("plane.off"), s);
  const Vec3d p{4.321, 5.678, 0.0};
  VertexId nearest = 0;
  for (VertexId v = 0; v < s.points.size(); ++v)
    if (norm(s.points[v] - p) < norm(s.points[nearest] - p)) nearest = v;
  // Nearest vertex: the same map as --seed-vertex.
  ASSERT_EQ(runTool({"distance", path("plane.off"), "--seed-point", "4.321,5.678,0.25", "-o", path("p.csv")}).exitCode, 0);
  ASSERT_EQ(runTool({"distance", path("plane.off"), "--seed-vertex", std::to_string(nearest), "-o", path("v.csv")})
                .exitCode,
            0);
  EXPECT_EQ(readDistances(path("p.csv")), readDistances(path("v.csv")));
  // The point itself, inserted into its face: distances from the point,
  // which on a plane are the straight lines, for the file's vertices only.
  const ToolRun run = runTool({"distance", path("plane.off"), "--seed-point", "4.321,5.678,0.25", "--seed-at",
                               "point", "-o", path("q.csv")});
  ASSERT_EQ(run.exitCode, 0) << run.err;
  EXPECT_NE(run.out.find("inserted as vertex 1681 at distance 0.2500 from the point"), std::string::npos) << run.out;
  const std::vector<double> d = readDistances(path("q.csv"));
  ASSERT_EQ(d.size(), s.points.size());
  double sum = 0.0;
  for (VertexId v = 0; v < d.size(); ++v) sum += std::abs(d[v] - norm(s.points[v] - p)) / norm(s.points[v] - p);
  const double mean = sum / d.size();
  std::printf("[ measured ] seed point inserted into a plane, STVD k=8: mean relative error %.5f\n", mean);
  EXPECT_LT(mean, 0.01);
  EXPECT_NEAR(d[nearest], norm(s.points[nearest] - p), 1e-3);

  // A point on an edge goes into that edge of both faces that share it.
  const std::uint32_t first = s.faces.faceStart[1000];
  const Vec3d a = s.points[s.faces.faceVertex[first]], b = s.points[s.faces.faceVertex[first + 1]];
  const Vec3d m = 0.5 * (a + b);
  std::ostringstream mid;
  mid.precision(17);
  mid << m.x << "," << m.y << "," << m.z;
  const ToolRun edge =
      runTool({"distance", path("plane.off"), "--seed-point", mid.str(), "--seed-at", "point", "-o", path("e.csv")});
  ASSERT_EQ(edge.exitCode, 0) << edge.err;
  EXPECT_NE(edge.out.find("on an edge of face"), std::string::npos) << edge.out;
  const std::vector<double> e = readDistances(path("e.csv"));
  EXPECT_NEAR(e[s.faces.faceVertex[first]], 0.5 * norm(b - a), 1e-6);
  EXPECT_NEAR(e[s.faces.faceVertex[first + 1]], 0.5 * norm(b - a), 1e-6);
}

TEST_F(ToolSurfaceParity, MaxDistanceStopsThePropagationAndStatsDescribeTheRun) {
  const GeneratedSurface s = test::planeMesh(20, 20, 10.0, 10.0, 0.5, 0.3, false, 9);
  writeOff(path("plane.off"), s);
  const ToolRun run = runTool({"distance", path("plane.off"), "--seed-vertex", "0", "--max-distance", "5",
                               "--method", "dijkstra", "-o", path("d.csv"), "--stats", path("s.json")});
  ASSERT_EQ(run.exitCode, 0) << run.err;
  const std::vector<double> d = readDistances(path("d.csv"));
  std::size_t reached = 0;
  for (const double x : d) {
    if (std::isfinite(x)) {
      ++reached;
      EXPECT_LE(x, 5.0);
    }
  }
  EXPECT_GT(reached, 20u);
  EXPECT_LT(reached, d.size() / 2);
  std::ifstream json(path("s.json"));
  std::stringstream text;
  text << json.rdbuf();
  for (const std::string& key : {std::string("\"max_distance\": 5"), std::string("\"vertices\": 441"), "\"reached\": " + std::to_string(reached),
                                std::string("\"method\": \"dijkstra\""), std::string("\"seconds\""),
                                std::string("\"peak_memory_bytes\"")})
    EXPECT_NE(text.str().find(key), std::string::npos) << key << " in " << text.str();
}

}  // namespace
}  // namespace stvd::testing
