// What the TetGen module checks before TetGen sees a surface: TetGen itself
// crashes on some bad input, so these checks are the first line of defence
// (the child process of `stvd tetrahedralize` is the second).
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <string>

#include "stvd/tetgen/tetrahedralize.hpp"

namespace stvd::tetgen {
namespace {

std::string problemOf(const SurfaceMesh& s) {
  try {
    validateSurface(s, "s.off");
  } catch (const tetmesh::TetMeshError& e) {
    return e.what();
  }
  return "";
}

TEST(SurfaceValidation, AcceptsAClosedBox) { EXPECT_EQ(problemOf(boxSurface({0, 0, 0}, {1, 2, 3})), ""); }

TEST(SurfaceValidation, AcceptsTrianglesWithRepeatedCornersAsStlWritesThem) {
  const SurfaceMesh box = boxSurface({0, 0, 0}, {1, 1, 1});
  SurfaceMesh stl;
  for (const auto& quad : box.polygons)
    for (int t = 0; t < 2; ++t) {
      const VertexId corners[3] = {quad[0], quad[1 + t], quad[2 + t]};
      std::vector<VertexId> triangle;
      for (VertexId c : corners) {
        triangle.push_back(static_cast<VertexId>(stl.points.size()));
        stl.points.push_back(box.points[c]);
      }
      stl.polygons.push_back(triangle);
    }
  EXPECT_EQ(problemOf(stl), "");
  tetrahedralizeSurface(stl, {}, "s.stl");  // and TetGen meshes it
}

TEST(SurfaceValidation, RejectsAnOpenSurface) {
  SurfaceMesh s = boxSurface({0, 0, 0}, {1, 1, 1});
  s.polygons.pop_back();
  EXPECT_NE(problemOf(s).find("s.off: the surface is not closed"), std::string::npos);
}

TEST(SurfaceValidation, RejectsANonFinitePoint) {
  SurfaceMesh s = boxSurface({0, 0, 0}, {1, 1, 1});
  s.points[3].y = std::numeric_limits<double>::quiet_NaN();
  EXPECT_NE(problemOf(s).find("s.off: point 3 has a non-finite coordinate"), std::string::npos);
}

TEST(SurfaceValidation, RejectsAZeroAreaPolygon) {
  SurfaceMesh s = boxSurface({0, 0, 0}, {1, 1, 1});
  s.points.push_back({0.5, 0, 0});
  s.polygons.push_back({0, 1, 8});  // three collinear corners
  EXPECT_NE(problemOf(s).find("polygon 6 is degenerate (zero area)"), std::string::npos);
}

TEST(SurfaceValidation, RejectsAPolygonWithFewerThanThreeDistinctCorners) {
  SurfaceMesh s = boxSurface({0, 0, 0}, {1, 1, 1});
  s.polygons.push_back({0, 1, 0});
  EXPECT_NE(problemOf(s).find("polygon 6 has fewer than three distinct corners"), std::string::npos);
}

TEST(SurfaceValidation, RejectsACornerOutOfRange) {
  SurfaceMesh s = boxSurface({0, 0, 0}, {1, 1, 1});
  s.polygons[2][1] = 99;
  EXPECT_NE(problemOf(s).find("polygon 2 has a corner out of range"), std::string::npos);
}

TEST(SurfaceValidation, BadOptionsAreRejectedBeforeMeshing) {
  TetrahedralizeOptions o;
  o.quality = 0.5;
  EXPECT_THROW(tetrahedralizeSurface(boxSurface({0, 0, 0}, {1, 1, 1}), o, "s"), std::invalid_argument);
  // Radius-edge bounds under which TetGen's refinement need not end (1.0
  // and 1.02 never did on this cube with a volume bound of 0.001).
  for (const double quality : {1.0, 1.02, 1.09}) {
    o.quality = quality;
    EXPECT_THROW(tetrahedralizeSurface(boxSurface({0, 0, 0}, {1, 1, 1}), o, "s"), std::invalid_argument) << quality;
  }
  o.quality = 2.0;
  o.maxVolume = -1.0;
  EXPECT_THROW(tetrahedralizeSurface(boxSurface({0, 0, 0}, {1, 1, 1}), o, "s"), std::invalid_argument);
  o.maxVolume.reset();
  o.maxAddedPoints = 0;
  EXPECT_THROW(tetrahedralizeSurface(boxSurface({0, 0, 0}, {1, 1, 1}), o, "s"), std::invalid_argument);
}

TEST(SurfaceValidation, AMeshNeedingMorePointsThanTheLimitIsAnError) {
  TetrahedralizeOptions o;
  o.quality = kMinimumQuality;
  o.maxVolume = 0.001;
  o.maxAddedPoints = 500;  // the mesh takes 1,481
  try {
    tetrahedralizeSurface(boxSurface({0, 0, 0}, {1, 1, 1}), o, "s");
    FAIL() << "no error";
  } catch (const tetmesh::TetMeshError& e) {
    EXPECT_NE(std::string(e.what()).find("needs more than the limit of 500 added points"), std::string::npos)
        << e.what();
  }
  o.maxAddedPoints = 5000;
  EXPECT_GT(tetrahedralizeSurface(boxSurface({0, 0, 0}, {1, 1, 1}), o, "s").vertexCount(), 1000u);
  // Refused before meshing: a box of 8 x 10^6 cubic units at a volume bound
  // of 1 asks for 10^6 points at least.
  o.maxVolume = 1.0;
  o.maxAddedPoints = 100'000;
  try {
    tetrahedralizeSurface(boxSurface({0, 0, 0}, {200, 200, 200}), o, "big");
    FAIL() << "no error";
  } catch (const tetmesh::TetMeshError& e) {
    EXPECT_NE(std::string(e.what()).find("big: a volume bound of 1 asks for at least 8e+06 tetrahedra"),
              std::string::npos)
        << e.what();
  }
}

}  // namespace
}  // namespace stvd::tetgen
