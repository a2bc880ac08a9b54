// TetGen .node/.ele/.face files: what is read, and the one-line errors for
// files that cannot be used. The writers: .vtk, .vtu, .csv and TetGen.
#include <gtest/gtest.h>
#include <unistd.h>

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

#include "stvd/tetmesh/tet_mesh.hpp"
#include "stvd/tetmesh/tet_mesh_writers.hpp"

namespace stvd::tetmesh {
namespace {

/// A fresh folder per test, with helpers to write text files; removed with
/// everything in it when the test ends.
class Folder {
 public:
  Folder() {
    std::string pattern = ::testing::TempDir() + "stvd_tetmesh_XXXXXX";
    if (::mkdtemp(pattern.data()) == nullptr) throw std::runtime_error("mkdtemp failed");
    path_ = pattern;
  }
  ~Folder() {
    std::error_code ignored;
    std::filesystem::remove_all(path_, ignored);
  }
  Folder(const Folder&) = delete;
  Folder& operator=(const Folder&) = delete;
  std::string file(const std::string& name, const std::string& text) const {
    const std::string p = path_ + "/" + name;
    std::ofstream(p) << text;
    return p;
  }
  std::string path(const std::string& name) const { return path_ + "/" + name; }

 private:
  std::string path_;
};

std::string slurp(const std::string& path) {
  std::ifstream in(path);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

// Two tetrahedra sharing the face (2, 3, 4) in 1-based numbering, with
// comments everywhere TetGen allows them, two point attributes, point
// markers, a region attribute per tetrahedron and a .face file.
const char* kNode1 =
    "# two tets\n"
    "5 3 2 1   # points dim attributes markers\n"
    "\n"
    "1  0 0 0    10 20   1\n"
    "2  1 0 0    11 21   0\n"
    "3  0 1 0    12 22   0\n"
    "4  0 0 1    13 23   0  # apex\n"
    "5  1 1 1    14 24   2\n";
const char* kEle1 =
    "2 4 1\n"
    "1  1 2 3 4   7\n"
    "2  2 5 3 4   -1.5\n";
const char* kFace1 =
    "1 1\n"
    "1  1 2 3  5\n";

TEST(TetGenReader, ReadsOneBasedFilesWithCommentsAttributesAndFaces) {
  Folder d;
  d.file("two.node", kNode1);
  d.file("two.ele", kEle1);
  d.file("two.face", kFace1);
  for (const std::string name : {"two", "two.node", "two.ele", "two.face"}) {
    const TetMesh m = readTetGenMesh(d.path(name));
    EXPECT_EQ(m.firstIndex, 1);
    ASSERT_EQ(m.vertexCount(), 5u);
    EXPECT_EQ(m.points[4].x, 1.0);
    EXPECT_EQ(m.points[3].z, 1.0);
    ASSERT_EQ(m.pointAttributeCount, 2u);
    EXPECT_EQ(m.pointAttributes[2 * 3 + 1], 23.0);
    EXPECT_EQ(m.pointMarkers[4], 2);
    ASSERT_EQ(m.tets.size(), 2u);
    EXPECT_EQ(m.tets[1], (std::array<VertexId, 4>{1, 4, 2, 3}));
    ASSERT_EQ(m.tetAttributeCount, 1u);
    EXPECT_EQ(m.tetAttributes[1], -1.5);
    ASSERT_EQ(m.faces.size(), 1u);
    EXPECT_EQ(m.faces[0], (std::array<VertexId, 3>{0, 1, 2}));
    EXPECT_EQ(m.faceMarkers[0], 5);
    EXPECT_EQ(m.fileNumber(0), 1);
  }
}

TEST(TetGenReader, ReadsZeroBasedFilesAndSecondOrderTetrahedra) {
  Folder d;
  d.file("z.node", "4 3 0 0\n0 0 0 0\n1 2 0 0\n2 0 2 0\n3 0 0 2\n");
  // Ten nodes: corners then edge midpoints (here any valid numbers).
  d.file("z.ele", "1 10 0\n0 0 1 2 3 0 1 2 3 0 1\n");
  const TetMesh m = readTetGenMesh(d.path("z.node"));
  EXPECT_EQ(m.firstIndex, 0);
  EXPECT_EQ(m.tets[0], (std::array<VertexId, 4>{0, 1, 2, 3}));
  EXPECT_TRUE(m.faces.empty());
  EXPECT_NEAR(signedVolume(m.points[0], m.points[1], m.points[2], m.points[3]), 8.0 / 6.0, 1e-15);
}

/// The message of the TetMeshError that reading `base` throws, or "".
std::string readError(const std::string& base) {
  try {
    readTetGenMesh(base);
  } catch (const TetMeshError& e) {
    return e.what();
  }
  return "";
}

struct BadFiles {
  const char* name;
  const char* node;
  const char* ele;
  const char* expected;  // file:line and the problem
};

const char* kGoodNode = "4 3 0 0\n1 0 0 0\n2 1 0 0\n3 0 1 0\n4 0 0 1\n";

class MalformedTetGenFiles : public ::testing::TestWithParam<BadFiles> {};

TEST_P(MalformedTetGenFiles, GiveOneLineNamingTheFileAndTheProblem) {
  const BadFiles& c = GetParam();
  Folder d;
  d.file("m.node", c.node);
  if (c.ele) d.file("m.ele", c.ele);
  const std::string message = readError(d.path("m"));
  ASSERT_FALSE(message.empty()) << c.name << ": no error";
  EXPECT_NE(message.find(c.expected), std::string::npos) << c.name << ": " << message;
  EXPECT_EQ(message.find('\n'), std::string::npos) << message;
}

INSTANTIATE_TEST_SUITE_P(
    TetGenReader, MalformedTetGenFiles,
    ::testing::Values(
        BadFiles{"fewer points than announced", "5 3 0 0\n1 0 0 0\n2 1 0 0\n3 0 1 0\n4 0 0 1\n", "1 4 0\n1 1 2 3 4\n",
                 "m.node: the header announces 5 points but the file has 4"},
        BadFiles{"more points than announced", "3 3 0 0\n1 0 0 0\n2 1 0 0\n3 0 1 0\n4 0 0 1\n", "1 4 0\n1 1 2 3 4\n",
                 "m.node:5: more lines than the 3 points"},
        BadFiles{"missing coordinate", "4 3 0 0\n1 0 0 0\n2 1 0\n3 0 1 0\n4 0 0 1\n", "1 4 0\n1 1 2 3 4\n",
                 "m.node:3: expected 4 values, found 3"},
        BadFiles{"attribute count not honoured", "4 3 1 0\n1 0 0 0\n2 1 0 0 5\n3 0 1 0 5\n4 0 0 1 5\n",
                 "1 4 0\n1 1 2 3 4\n", "m.node:2: expected 5 values, found 4"},
        BadFiles{"not a number", "4 3 0 0\n1 0 0 0\n2 1 x 0\n3 0 1 0\n4 0 0 1\n", "1 4 0\n1 1 2 3 4\n",
                 "m.node:3: y 'x' is not a number"},
        BadFiles{"non-finite coordinate", "4 3 0 0\n1 0 0 0\n2 1 nan 0\n3 0 1 0\n4 0 0 1\n", "1 4 0\n1 1 2 3 4\n",
                 "m.node:3: y 'nan' is not finite"},
        BadFiles{"two-dimensional", "4 2 0 0\n1 0 0\n2 1 0\n3 0 1\n4 1 1\n", "1 4 0\n1 1 2 3 4\n",
                 "m.node:1: dimension 2"},
        BadFiles{"numbering from 2", "4 3 0 0\n2 0 0 0\n3 1 0 0\n4 0 1 0\n5 0 0 1\n", "1 4 0\n1 2 3 4 5\n",
                 "m.node:2: the first point is numbered 2"},
        BadFiles{"gap in numbering", "4 3 0 0\n1 0 0 0\n2 1 0 0\n4 0 1 0\n5 0 0 1\n", "1 4 0\n1 1 2 3 4\n",
                 "m.node:4: point number 4 where 3 was expected"},
        BadFiles{"negative count", "-4 3 0 0\n", "1 4 0\n1 1 2 3 4\n", "m.node:1: point count -4 is out of range"},
        BadFiles{"no .ele file", kGoodNode, nullptr, "m.ele: cannot open the file"},
        BadFiles{"fewer tetrahedra than announced", kGoodNode, "2 4 0\n1 1 2 3 4\n",
                 "m.ele: the header announces 2 tetrahedra but the file has 1"},
        BadFiles{"five nodes per tetrahedron", kGoodNode, "1 5 0\n1 1 2 3 4 1\n",
                 "m.ele:1: nodes per tetrahedron must be 4 or 10, not 5"},
        BadFiles{"corner out of range", kGoodNode, "1 4 0\n1 1 2 3 5\n",
                 "m.ele:2: tetrahedron corner 5 is out of range (points are numbered 1..4)"},
        BadFiles{"zero corner in a 1-based file", kGoodNode, "1 4 0\n1 0 2 3 4\n",
                 "m.ele:2: tetrahedron corner 0 is out of range"},
        BadFiles{"tetrahedra numbered from 0 in a 1-based file", kGoodNode, "1 4 0\n0 1 2 3 4\n",
                 "m.ele:2: tetrahedron number 0 where 1 was expected"},
        BadFiles{"repeated corner", kGoodNode, "1 4 0\n1 1 2 2 4\n", "m.ele: tetrahedron 1 repeats corner 2"},
        BadFiles{"inverted tetrahedron", kGoodNode, "1 4 0\n1 2 1 3 4\n", "m.ele: tetrahedron 1 is inverted"},
        BadFiles{"flat tetrahedron", "4 3 0 0\n1 0 0 0\n2 1 0 0\n3 0 1 0\n4 1 1 0\n", "1 4 0\n1 1 2 3 4\n",
                 "m.ele: tetrahedron 1 is degenerate"},
        BadFiles{"coinciding corners", "4 3 0 0\n1 0 0 0\n2 1 0 0\n3 0 1 0\n4 0 1 0\n", "1 4 0\n1 1 2 3 4\n",
                 "m.ele: tetrahedron 1 is degenerate"},
        BadFiles{"empty .ele", kGoodNode, "# nothing\n", "m.ele: empty file"}),
    [](const ::testing::TestParamInfo<BadFiles>& info) {
      std::string n = info.param.name;
      for (char& c : n)
        if (!std::isalnum(static_cast<unsigned char>(c))) c = '_';
      return n;
    });

TEST(TetGenReader, AMissingNodeFileIsNamed) {
  Folder d;
  EXPECT_NE(readError(d.path("absent.node")).find("absent.node: cannot open the file"), std::string::npos);
}

TEST(TetGenReader, AFaceCornerOutOfRangeIsAnError) {
  Folder d;
  d.file("f.node", kGoodNode);
  d.file("f.ele", "1 4 0\n1 1 2 3 4\n");
  d.file("f.face", "1 0\n1 1 2 9\n");
  EXPECT_NE(readError(d.path("f")).find("f.face:2: face corner 9 is out of range"), std::string::npos);
}

TEST(TetGenWriter, WritesFilesThatReadBackExactly) {
  Folder d;
  d.file("two.node", kNode1);
  d.file("two.ele", kEle1);
  d.file("two.face", kFace1);
  TetMesh m = readTetGenMesh(d.path("two"));
  m.points[4] = {1.0 / 3.0, 1.1, 0.7e-300 + 1.0};  // still a valid second tetrahedron
  writeTetGenMesh(d.path("copy"), m);
  const TetMesh r = readTetGenMesh(d.path("copy.node"));
  EXPECT_EQ(r.firstIndex, 1);
  EXPECT_EQ(r.points[4].x, m.points[4].x);
  EXPECT_EQ(r.points[4].y, m.points[4].y);
  EXPECT_EQ(r.tets, m.tets);
  EXPECT_EQ(r.faces, m.faces);
  EXPECT_EQ(r.pointAttributes, m.pointAttributes);
  EXPECT_EQ(r.pointMarkers, m.pointMarkers);
  EXPECT_EQ(r.tetAttributes, m.tetAttributes);
  EXPECT_EQ(r.faceMarkers, m.faceMarkers);
}

TEST(TetMeshOutput, CsvNamesVerticesAsTheInputFileDoes) {
  Folder d;
  d.file("two.node", kNode1);
  d.file("two.ele", kEle1);
  const TetMesh m = readTetGenMesh(d.path("two"));
  writeCsv(d.path("out.csv"), m, {{"distance", {0.0, 1.0, 0.5, 0.25, -1.0}}});
  EXPECT_EQ(slurp(d.path("out.csv")), "vertex,distance\n1,0\n2,1\n3,0.5\n4,0.25\n5,-1\n");
}

TEST(TetMeshOutput, LegacyVtkHoldsPointsTetraCellsAndPointData) {
  Folder d;
  d.file("two.node", kNode1);
  d.file("two.ele", kEle1);
  const TetMesh m = readTetGenMesh(d.path("two"));
  writeVtkLegacy(d.path("out.vtk"), m, {{"distance", {0.0, 1.0, 0.5, 0.25, 2.0}}});
  const std::string text = slurp(d.path("out.vtk"));
  EXPECT_EQ(text.rfind("# vtk DataFile Version 3.0\n", 0), 0u);
  EXPECT_NE(text.find("DATASET UNSTRUCTURED_GRID\nPOINTS 5 double\n"), std::string::npos);
  // 0-based connectivity, whatever the input's numbering.
  EXPECT_NE(text.find("CELLS 2 10\n4 0 1 2 3\n4 1 4 2 3\n"), std::string::npos);
  EXPECT_NE(text.find("CELL_TYPES 2\n10\n10\n"), std::string::npos);
  EXPECT_NE(text.find("POINT_DATA 5\nSCALARS distance double 1\nLOOKUP_TABLE default\n0\n1\n0.5\n0.25\n2\n"),
            std::string::npos);
  EXPECT_NE(text.find("SCALARS vertex_number long 1\nLOOKUP_TABLE default\n1\n2\n3\n4\n5\n"), std::string::npos);
}

TEST(TetMeshOutput, VtuIsAnUnstructuredGridWithOffsetsAndTypes) {
  Folder d;
  d.file("two.node", kNode1);
  d.file("two.ele", kEle1);
  const TetMesh m = readTetGenMesh(d.path("two"));
  writeVtu(d.path("out.vtu"), m, {{"distance", {0.0, 1.0, 0.5, 0.25, 2.0}}});
  const std::string text = slurp(d.path("out.vtu"));
  EXPECT_NE(text.find("<VTKFile type=\"UnstructuredGrid\""), std::string::npos);
  EXPECT_NE(text.find("<Piece NumberOfPoints=\"5\" NumberOfCells=\"2\">"), std::string::npos);
  EXPECT_NE(text.find("Name=\"connectivity\" format=\"ascii\">\n0 1 2 3\n1 4 2 3\n"), std::string::npos);
  EXPECT_NE(text.find("Name=\"offsets\" format=\"ascii\">\n4\n8\n"), std::string::npos);
  EXPECT_NE(text.find("Name=\"types\" format=\"ascii\">\n10\n10\n"), std::string::npos);
  EXPECT_NE(text.find("Name=\"distance\" format=\"ascii\">\n0\n1\n0.5\n0.25\n2\n"), std::string::npos);
  EXPECT_NE(text.find("</VTKFile>"), std::string::npos);
}

TEST(TetMeshOutput, FormatFollowsTheExtension) {
  TetMeshOutputFormat f;
  ASSERT_TRUE(outputFormatOf("a/b.VTU", f));
  EXPECT_EQ(f, TetMeshOutputFormat::Vtu);
  ASSERT_TRUE(outputFormatOf("b.vtk", f));
  EXPECT_EQ(f, TetMeshOutputFormat::VtkLegacy);
  ASSERT_TRUE(outputFormatOf("b.csv", f));
  EXPECT_EQ(f, TetMeshOutputFormat::Csv);
  EXPECT_FALSE(outputFormatOf("b.nii.gz", f));
  EXPECT_FALSE(outputFormatOf("dir.vtk/b", f));
}

TEST(TetMeshQueries, ContainingTetAndNearestVertex) {
  Folder d;
  d.file("two.node", kNode1);
  d.file("two.ele", kEle1);
  const TetMesh m = readTetGenMesh(d.path("two"));
  EXPECT_EQ(findContainingTet(m, {0.1, 0.1, 0.1}), 0);
  EXPECT_EQ(findContainingTet(m, {0.6, 0.6, 0.6}), 1);
  EXPECT_EQ(findContainingTet(m, {2.0, 0.0, 0.0}), -1);
  EXPECT_EQ(nearestVertex(m, {0.9, 0.8, 1.2}), 4u);
}

}  // namespace
}  // namespace stvd::tetmesh
