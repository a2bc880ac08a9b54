// Surface files: .obj, .off and .ply (ASCII, binary little- and big-endian)
// written byte by byte here, read into the same mesh; errors name the file
// and the line or element; the distance writers' .ply, .vtk and .csv.
#include <gtest/gtest.h>
#include <sys/resource.h>
#include <unistd.h>

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <limits>
#include <sstream>
#include <string>

#include "stvd/surface_io/surface_mesh_io.hpp"

#if defined(__has_feature)
#if __has_feature(address_sanitizer)
#define STVD_HAS_ASAN 1
#endif
#endif
#ifndef STVD_HAS_ASAN
#define STVD_HAS_ASAN 0
#endif

namespace stvd::surface_io {
namespace {

namespace fs = std::filesystem;

class SurfaceFiles : public ::testing::Test {
 protected:
  void SetUp() override {
    folder_ = fs::temp_directory_path() /
              ("stvd-surface-io-" + std::to_string(::testing::UnitTest::GetInstance()->random_seed()) +
               "-" + ::testing::UnitTest::GetInstance()->current_test_info()->name());
    fs::remove_all(folder_);
    fs::create_directories(folder_);
  }
  void TearDown() override { fs::remove_all(folder_); }
  std::string write(const std::string& name, const std::string& bytes) const {
    const std::string p = (folder_ / name).string();
    std::ofstream(p, std::ios::binary) << bytes;
    return p;
  }
  std::string path(const std::string& name) const { return (folder_ / name).string(); }
  static std::string errorOf(const std::string& p) {
    try {
      readSurfaceMesh(p);
    } catch (const MeshFileError& e) {
      return e.what();
    }
    return "";
  }

 private:
  fs::path folder_;
};

// The reference mesh of these files: a unit square as one quad and a
// triangle on top, vertices 0..4.
void expectReferenceMesh(const SurfaceMesh& m) {
  ASSERT_EQ(m.points.size(), 5u);
  EXPECT_EQ(m.points[2].x, 1.0);
  EXPECT_EQ(m.points[2].y, 1.0);
  EXPECT_EQ(m.points[4].x, 0.5);
  EXPECT_EQ(m.points[4].y, 2.0);
  EXPECT_EQ(m.points[4].z, -0.25);
  ASSERT_EQ(m.faces.faceCount(), 2u);
  EXPECT_EQ(m.faces.faceStart, (std::vector<std::uint32_t>{0, 4, 7}));
  EXPECT_EQ(m.faces.faceVertex, (std::vector<VertexId>{0, 1, 2, 3, 3, 2, 4}));
}

TEST_F(SurfaceFiles, ObjWithTextureAndNormalIndicesAndNegativeIndices) {
  expectReferenceMesh(readSurfaceMesh(write("m.OBJ",
                                            "# square and roof\r\n"
                                            "mtllib x.mtl\n"
                                            "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\n"
                                            "vt 0 0\nvn 0 0 1\n"
                                            "g roof\n"
                                            "f 1/1/1 2/1/1 3//1 4\n"
                                            "v 0.5 2 -0.25  # apex\n"
                                            "f -2 -3 -1\n")));
}

TEST_F(SurfaceFiles, ObjErrorsNameTheLine) {
  EXPECT_EQ(errorOf(write("a.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 9\n")),
            path("a.obj") + ": line 4: vertex index 9 refers to no vertex defined so far (3)");
  EXPECT_EQ(errorOf(write("b.obj", "v 0 0\n")),
            path("b.obj") + ": line 1: a vertex needs three finite coordinates");
  EXPECT_EQ(errorOf(write("c.obj", "v 0 0 0\n")), path("c.obj") + ": the file has no faces");
}

TEST_F(SurfaceFiles, OffWithCommentsAndColours) {
  expectReferenceMesh(readSurfaceMesh(write("m.off",
                                            "COFF\n# counts\n5 2 0\n"
                                            "0 0 0 255 0 0 255\n1 0 0 255 0 0 255\n"
                                            "1 1 0 255 0 0 255\n0 1 0 255 0 0 255\n"
                                            "0.5 2 -0.25 255 0 0 255\n"
                                            "4 0 1 2 3\n3 3 2 4 10 20 30\n")));
  expectReferenceMesh(readSurfaceMesh(write(
      "n.off", "OFF 5 2 0\n0 0 0\n1 0 0\n1 1 0\n0 1 0\n0.5 2 -0.25\n4 0 1 2 3\n3 3 2 4\n")));
}

TEST_F(SurfaceFiles, OffErrorsNameTheLineAndElement) {
  EXPECT_EQ(errorOf(write("a.off", "OFF\n4 1 0\n0 0 0\n1 0 0\n")),
            path("a.off") + ": the file ends after 2 of 4 vertices");
  EXPECT_EQ(errorOf(write("b.off", "OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 3\n")),
            path("b.off") + ": line 6: face 0: vertex index \"3\" is not one of the 3 vertices");
  EXPECT_EQ(errorOf(write("c.off", "PLY\n")),
            path("c.off") + ": line 1: not an OFF file (the first word is \"PLY\")");
}

const char* kPlyAscii =
    "ply\nformat ascii 1.0\ncomment made by hand\n"
    "element vertex 5\nproperty float x\nproperty float y\nproperty float z\n"
    "property uchar red\n"
    "element edge 1\nproperty int vertex1\nproperty int vertex2\n"
    "element face 2\nproperty list uchar int vertex_indices\nproperty float quality\n"
    "end_header\n"
    "0 0 0 9\n1 0 0 9\n1 1 0 9\n0 1 0 9\n0.5 2 -0.25 9\n"
    "0 1\n"
    "4 0 1 2 3 0.5\n3 3 2 4 0.5\n";

/// The reference mesh in binary PLY: double coordinates, a ushort property
/// between them, uint indices with a uchar count, in the given byte order.
std::string binaryPly(bool littleEndian) {
  std::string s = std::string("ply\nformat ") +
                  (littleEndian ? "binary_little_endian" : "binary_big_endian") +
                  " 1.0\nelement vertex 5\nproperty double x\nproperty ushort flags\n"
                  "property double y\nproperty double z\n"
                  "element face 2\nproperty list uchar uint vertex_indices\nend_header\n";
  auto put = [&](const void* p, std::size_t n) {
    std::string b(static_cast<const char*>(p), n);
    const std::uint16_t one = 1;
    const bool hostLittle = *reinterpret_cast<const unsigned char*>(&one) == 1;
    if (hostLittle != littleEndian) std::reverse(b.begin(), b.end());
    s += b;
  };
  const double xyz[5][3] = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}, {0.5, 2, -0.25}};
  for (const auto& p : xyz) {
    const std::uint16_t flags = 0xABCD;
    put(&p[0], 8);
    put(&flags, 2);
    put(&p[1], 8);
    put(&p[2], 8);
  }
  const std::vector<std::vector<std::uint32_t>> faces{{0, 1, 2, 3}, {3, 2, 4}};
  for (const auto& f : faces) {
    const std::uint8_t n = static_cast<std::uint8_t>(f.size());
    put(&n, 1);
    for (const std::uint32_t i : f) put(&i, 4);
  }
  return s;
}

TEST_F(SurfaceFiles, PlyAsciiAndBinaryOfBothByteOrdersGiveTheSameMesh) {
  expectReferenceMesh(readSurfaceMesh(write("a.ply", kPlyAscii)));
  expectReferenceMesh(readSurfaceMesh(write("le.ply", binaryPly(true))));
  expectReferenceMesh(readSurfaceMesh(write("be.ply", binaryPly(false))));
}

TEST_F(SurfaceFiles, PlyErrorsNameTheElement) {
  std::string truncated = binaryPly(true);
  truncated.resize(truncated.size() - 3);
  EXPECT_EQ(errorOf(write("t.ply", truncated)), path("t.ply") + ": face 1: the file ends early");
  std::string badIndex = kPlyAscii;
  badIndex.replace(badIndex.find("3 3 2 4"), 7, "3 3 2 7");
  EXPECT_EQ(errorOf(write("i.ply", badIndex)),
            path("i.ply") + ": face 1: vertex index 7 is not one of the 5 vertices");
  EXPECT_EQ(errorOf(write("f.ply", "ply\nformat binary_middle_endian 1.0\nend_header\n")),
            path("f.ply") + ": line 2: unknown PLY format \"binary_middle_endian\"");
  EXPECT_EQ(errorOf(path("missing.ply")).rfind(path("missing.ply") + ": cannot open the file", 0), 0u);
}

// Hostile sizes: a count the file cannot hold is refused, or read until the
// file ends, without anything allocated or looped over for it. The reader
// runs in a child process that an alarm ends after 20 s (a hang fails the
// test instead of stalling it) and, outside AddressSanitizer builds, with
// 1 GB of address space.
[[noreturn]] void readInALimitedChild(const std::string& p, const std::string& expectedError) {
  alarm(20);
#if !defined(__SANITIZE_ADDRESS__) && !STVD_HAS_ASAN
  rlimit limit{};
  limit.rlim_cur = limit.rlim_max = rlim_t{1} << 30;
  setrlimit(RLIMIT_AS, &limit);
#endif
  std::string error;
  try {
    readSurfaceMesh(p);
  } catch (const MeshFileError& e) {
    error = e.what();
  }
  if (error != expectedError) std::fprintf(stderr, "the error was \"%s\"\n", error.c_str());
  std::_Exit(error == expectedError ? 0 : 1);
}

void expectReadEndsWithin20SecondsIn1GB(const std::string& p, const std::string& expectedError) {
  EXPECT_EXIT(readInALimitedChild(p, expectedError), ::testing::ExitedWithCode(0), "")
      << "expected the error \"" << expectedError << "\"";
}

TEST_F(SurfaceFiles, PlyElementOfBillionsOfEmptyRecordsIsNotLoopedOver) {
  std::string ply = kPlyAscii;
  ply.insert(ply.find("end_header"), "element padding 9223372036854775807\n");
  expectReadEndsWithin20SecondsIn1GB(write("p.ply", ply), "");
}

TEST_F(SurfaceFiles, PlyCountsBeyondTheFileAreRefusedUpFront) {
  expectReadEndsWithin20SecondsIn1GB(
      write("v.ply",
            "ply\nformat binary_little_endian 1.0\nelement vertex 10000000000\nproperty float x\n"
            "property float y\nproperty float z\nend_header\n0123456789AB"),
      path("v.ply") + ": the header announces 10000000000 vertex records, more than the 12 bytes left in the "
                      "file can hold");
}

TEST_F(SurfaceFiles, OffCountsBeyondTheFileReserveNothingForThem) {
  expectReadEndsWithin20SecondsIn1GB(write("v.off", "OFF\n67108864 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n"),
                                     path("v.off") + ": the file ends after 4 of 67108864 vertices");
  expectReadEndsWithin20SecondsIn1GB(write("w.off", "OFF\n10000000000 1 0\n0 0 0\n1 0 0\n0 1 0\n"),
                                     path("w.off") + ": the file ends after 3 of 10000000000 vertices");
  expectReadEndsWithin20SecondsIn1GB(
      write("f.off", "OFF\n3 9223372036854775807 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n"),
      path("f.off") + ": the file ends after 1 of 9223372036854775807 faces");
}

TEST_F(SurfaceFiles, DistancesAreWrittenAsPlyVtkAndCsv) {
  const SurfaceMesh m = readSurfaceMesh(write("m.ply", kPlyAscii));
  const std::vector<double> d{0.0, 1.0, 1.5, 1.0, std::numeric_limits<double>::infinity()};
  writeSurfaceDistances(path("d.csv"), path("d.csv"), m, d);
  std::ifstream csv(path("d.csv"));
  std::stringstream text;
  text << csv.rdbuf();
  EXPECT_EQ(text.str(), "vertex,distance\n0,0\n1,1\n2,1.5\n3,1\n4,inf\n");

  writeSurfaceDistances(path("staged.tmp"), path("d.vtk"), m, d);
  std::ifstream vtk(path("staged.tmp"));
  std::stringstream v;
  v << vtk.rdbuf();
  EXPECT_NE(v.str().find("DATASET POLYDATA\nPOINTS 5 double\n"), std::string::npos);
  EXPECT_NE(v.str().find("POLYGONS 2 9\n4 0 1 2 3\n3 3 2 4\n"), std::string::npos);
  EXPECT_NE(v.str().find("POINT_DATA 5\nSCALARS distance double 1\nLOOKUP_TABLE default\n0\n1\n1.5\n1\n-1\n"),
            std::string::npos);

  // The .ply reads back as the same mesh; its distance column is checked
  // from the bytes (x y z float as in the input, distance float,
  // little-endian).
  writeSurfaceDistances(path("d.ply"), path("d.ply"), m, d);
  expectReferenceMesh(readSurfaceMesh(path("d.ply")));
  std::ifstream ply(path("d.ply"), std::ios::binary);
  std::string bytes((std::istreambuf_iterator<char>(ply)), std::istreambuf_iterator<char>());
  EXPECT_NE(bytes.find("property float x\nproperty float y\nproperty float z\nproperty float distance\n"),
            std::string::npos);
  const std::size_t body = bytes.find("end_header\n") + 11;
  for (std::size_t v2 = 0; v2 < 5; ++v2) {
    float value;
    std::memcpy(&value, bytes.data() + body + v2 * 16 + 12, 4);
    EXPECT_EQ(value, static_cast<float>(d[v2]));
  }
}

// Vertices are written back exactly as they were read: in the input's
// coordinate type (double coordinates are not rounded to float), and the
// distance in the type the header declares.
TEST_F(SurfaceFiles, PlyOutputKeepsTheCoordinateTypeAndDeclaresItsDistanceType) {
  const std::string text =
      "ply\nformat ascii 1.0\nelement vertex 3\nproperty double x\nproperty double y\nproperty double z\n"
      "element face 1\nproperty list uchar int vertex_indices\nend_header\n"
      "0.12345678912345678 0 0\n1 0.98765432198765432 0\n0 1 1e-7\n3 0 1 2\n";
  const SurfaceMesh m = readSurfaceMesh(write("double.ply", text));
  EXPECT_EQ(m.coordinateType, ScalarType::Float64);
  writeSurfaceDistances(path("out.ply"), path("out.ply"), m, {0.0, std::sqrt(2.0), 1.0});
  const SurfaceMesh back = readSurfaceMesh(path("out.ply"));
  for (std::size_t v = 0; v < 3; ++v) {
    EXPECT_EQ(back.points[v].x, m.points[v].x) << v;
    EXPECT_EQ(back.points[v].y, m.points[v].y) << v;
    EXPECT_EQ(back.points[v].z, m.points[v].z) << v;
  }
  std::ifstream ply(path("out.ply"), std::ios::binary);
  const std::string bytes((std::istreambuf_iterator<char>(ply)), std::istreambuf_iterator<char>());
  ASSERT_NE(bytes.find("property double z\nproperty float distance\n"), std::string::npos);
  float root2;
  std::memcpy(&root2, bytes.data() + bytes.find("end_header\n") + 11 + 28 + 24, 4);
  EXPECT_EQ(root2, static_cast<float>(std::sqrt(2.0)));
}

// STL lists three corners per facet: equal corners become one vertex.
TEST_F(SurfaceFiles, StlInAsciiAndBinaryIsWeldedIntoTheReferenceMesh) {
  // Two triangles sharing an edge, and a facet with two equal corners.
  const std::string ascii =
      "solid two\n facet normal 0 0 1\n  outer loop\n   vertex 0 0 0\n   vertex 1 0 0\n   vertex 1 1 0\n"
      "  endloop\n endfacet\n facet normal 0 0 1\n  outer loop\n   vertex 0 0 0\n   vertex 1 1 0\n"
      "   vertex 0 1 0\n  endloop\n endfacet\n facet normal 0 0 1\n outer loop\n vertex 0 0 0\n"
      " vertex 0 0 0\n vertex 0 1 0\n endloop\n endfacet\nendsolid two\n";
  SurfaceMesh m = readSurfaceMesh(write("a.stl", ascii));
  EXPECT_EQ(m.points.size(), 4u);
  EXPECT_EQ(m.faces.faceCount(), 2u);
  EXPECT_EQ(m.weldedVertices, 5u);  // 9 corners, 4 vertices
  EXPECT_EQ(m.degenerateFacets, 1u);
  EXPECT_EQ(m.coordinateType, ScalarType::Float64);
  // Binary, its header starting with "solid" as some exporters write it.
  std::string binary = "solid but binary";
  binary.resize(80, ' ');
  const std::uint32_t count = 2;
  binary.append(reinterpret_cast<const char*>(&count), 4);
  const float facets[2][12] = {{0, 0, 1, 0, 0, 0, 1, 0, 0, 1, 1, 0}, {0, 0, 1, 0, 0, 0, 1, 1, 0, 0, 1, 0}};
  for (const auto& f : facets) {
    binary.append(reinterpret_cast<const char*>(f), 48);
    binary.append(2, '\0');
  }
  m = readSurfaceMesh(write("b.stl", binary));
  EXPECT_EQ(m.points.size(), 4u);
  EXPECT_EQ(m.faces.faceCount(), 2u);
  EXPECT_EQ(m.weldedVertices, 2u);
  EXPECT_EQ(m.coordinateType, ScalarType::Float32);
  EXPECT_EQ(m.points[2].x, 1.0);
  EXPECT_EQ(m.points[3].y, 1.0);
  // A binary count that the file does not hold is no STL, without allocating for it.
  std::string hostile = binary.substr(0, 80);
  const std::uint32_t absurd = 4000000000u;
  hostile.append(reinterpret_cast<const char*>(&absurd), 4);
  hostile.append(100, '\0');
  hostile[0] = 'x';
  EXPECT_NE(errorOf(write("h.stl", hostile)).find("not an STL file"), std::string::npos);
  EXPECT_NE(errorOf(write("t.stl", "solid t\n facet normal 0 0 1\n outer loop\n vertex 0 0 0\n")).find("ends inside a facet"),
            std::string::npos);
}

TEST_F(SurfaceFiles, VertexTablesSkipAHeaderAndNameBadRows) {
  const auto t = readVertexTable(write("t.csv", "dx,dy,dz\n1,0,0\n# note\n0, 1, 0\n"), 3, 2);
  EXPECT_EQ(t[1], (std::vector<double>{0, 1, 0}));
  try {
    readVertexTable(write("u.txt", "1 0 0\n1 0\n"), 3, 2);
    FAIL();
  } catch (const MeshFileError& e) {
    EXPECT_EQ(std::string(e.what()),
              path("u.txt") + ": line 2: expected 3 finite numbers (the values of vertex 1)");
  }
  try {
    readVertexTable(write("v.txt", "1 0 0\n"), 3, 2);
    FAIL();
  } catch (const MeshFileError& e) {
    EXPECT_EQ(std::string(e.what()), path("v.txt") + ": 1 rows for 2 vertices");
  }
}

}  // namespace
}  // namespace stvd::surface_io
