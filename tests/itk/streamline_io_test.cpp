// Streamline files as the standard readers see them: .tck and .trk loaded
// by nibabel, .vtk by an independent parser, with every point compared to
// the expected RAS millimetres, on an oblique grid whose first axis points
// left (so that the LPS -> RAS flip and the .trk voxel order both matter).
#include <gtest/gtest.h>

#include <cmath>

#include "stvd/errors.hpp"
#include "stvd/imaging/streamline_io.hpp"
#include "streamline_reading.hpp"
#include "test_support.hpp"

namespace stvd::testing {
namespace {

// float32 storage of coordinates up to ~150 mm rounds by about 1e-5 mm
// (.trk also through its float32 voxel-to-RAS matrix).
constexpr double kCoordinateTolerance = 1e-4;

imaging::StreamlineSet exampleSet() {
  imaging::StreamlineSet set;
  HandGeometry h;
  h.size = {40, 30, 20};
  h.spacing = {2.0, 1.5, 2.5};
  h.originLps = {37.5, -21.0, -12.25};
  // First index axis towards the patient's left, second anterior: "LAS",
  // tilted by 7 degrees.
  h.directionLps = multiply(rotation(0.3, -0.2, 1.0, 7.0), {1, 0, 0, 0, -1, 0, 0, 0, 1});
  set.geometry = h.grid();
  const GridGeometry& g = set.geometry;
  set.lines = {{g.indexToPhysicalPoint(0, 0, 0), g.indexToPhysicalPoint(3.25, 7.5, 1.75), g.indexToPhysicalPoint(39, 29, 19)},
               {g.indexToPhysicalPoint(10, 12, 5), g.indexToPhysicalPoint(10.5, 12.5, 5.5)},
               {g.indexToPhysicalPoint(20.2, 0.1, 18.9), g.indexToPhysicalPoint(21, 1, 18), g.indexToPhysicalPoint(22, 2, 17),
                g.indexToPhysicalPoint(23, 3, 16)}};
  set.lineValueNames = {"geodesic_mm", "euclidean_mm"};
  set.lineValues = {{101.5f, 2.25f, 17.0f}, {88.0f, 1.5f, 9.75f}};
  set.pointValueNames = {"fa"};
  set.pointValues = {{{0.1f, 0.2f, 0.3f}, {0.4f, 0.5f}, {0.6f, 0.7f, 0.8f, 0.9f}}};
  return set;
}

void expectSameLinesInRas(const LoadedStreamlines& loaded, const imaging::StreamlineSet& set) {
  ASSERT_EQ(loaded.error, "");
  ASSERT_EQ(loaded.lines.size(), set.lines.size());
  for (std::size_t l = 0; l < set.lines.size(); ++l) {
    ASSERT_EQ(loaded.lines[l].size(), set.lines[l].size());
    for (std::size_t p = 0; p < set.lines[l].size(); ++p) {
      const Vec3d lps = set.lines[l][p];
      const Vec3d ras{-lps.x, -lps.y, lps.z};
      EXPECT_NEAR(loaded.lines[l][p].x, ras.x, kCoordinateTolerance) << "line " << l << " point " << p;
      EXPECT_NEAR(loaded.lines[l][p].y, ras.y, kCoordinateTolerance) << "line " << l << " point " << p;
      EXPECT_NEAR(loaded.lines[l][p].z, ras.z, kCoordinateTolerance) << "line " << l << " point " << p;
    }
  }
}

class StreamlineFiles : public ScratchFolderTest {};

TEST_F(StreamlineFiles, VoxelToRasIsTheNiftiAffineAndItsAxisCodesNameTheAxes) {
  const imaging::StreamlineSet set = exampleSet();
  const std::array<double, 16> m = imaging::voxelToRas(set.geometry);
  const Vec3d lps = set.geometry.indexToPhysicalPoint(3, 4, 5);
  EXPECT_NEAR(m[0] * 3 + m[1] * 4 + m[2] * 5 + m[3], -lps.x, 1e-9);
  EXPECT_NEAR(m[4] * 3 + m[5] * 4 + m[6] * 5 + m[7], -lps.y, 1e-9);
  EXPECT_NEAR(m[8] * 3 + m[9] * 4 + m[10] * 5 + m[11], lps.z, 1e-9);
  EXPECT_EQ(imaging::rasAxisCodes(set.geometry), "LAS");
}

TEST_F(StreamlineFiles, TckLoadsInNibabelWithTheSameRasPoints) {
  const imaging::StreamlineSet set = exampleSet();
  imaging::writeStreamlines(path("paths.tck"), set);
  const LoadedStreamlines loaded = loadWithNibabel(path("paths.tck"));
  expectSameLinesInRas(loaded, set);
  EXPECT_EQ(loaded.header.at("count"), "3");
  EXPECT_EQ(loaded.header.at("geodesic_mm"), "101.5_2.25_17");
}

TEST_F(StreamlineFiles, TrkLoadsInNibabelWithTheSameRasPointsScalarsAndProperties) {
  const imaging::StreamlineSet set = exampleSet();
  imaging::writeStreamlines(path("paths.trk"), set);
  const LoadedStreamlines loaded = loadWithNibabel(path("paths.trk"));
  expectSameLinesInRas(loaded, set);
  EXPECT_EQ(loaded.header.at("voxel_order"), "LAS");
  ASSERT_EQ(loaded.perLine.count("geodesic_mm"), 1u);
  ASSERT_EQ(loaded.perLine.count("euclidean_mm"), 1u);
  for (std::size_t l = 0; l < set.lines.size(); ++l) {
    EXPECT_EQ(loaded.perLine.at("geodesic_mm")[l], set.lineValues[0][l]);
    EXPECT_EQ(loaded.perLine.at("euclidean_mm")[l], set.lineValues[1][l]);
    for (std::size_t p = 0; p < set.lines[l].size(); ++p)
      EXPECT_EQ(loaded.perPoint.at("fa")[l][p], set.pointValues[0][l][p]);
  }
}

TEST_F(StreamlineFiles, VtkHoldsRasPointsLinesAndValues) {
  const imaging::StreamlineSet set = exampleSet();
  imaging::writeStreamlines(path("paths.vtk"), set);
  const LoadedStreamlines loaded = loadLegacyVtk(path("paths.vtk"));
  expectSameLinesInRas(loaded, set);
  EXPECT_NE(loaded.header.at("title").find("SPACE=RAS"), std::string::npos);
  for (std::size_t l = 0; l < set.lines.size(); ++l) {
    EXPECT_EQ(loaded.perLine.at("geodesic_mm")[l], set.lineValues[0][l]);
    for (std::size_t p = 0; p < set.lines[l].size(); ++p)
      EXPECT_FLOAT_EQ(loaded.perPoint.at("fa")[l][p], set.pointValues[0][l][p]);
  }
}

TEST_F(StreamlineFiles, BadRequestsNameTheFileAndLeaveNothingBehind) {
  imaging::StreamlineSet set = exampleSet();
  EXPECT_THROW(imaging::writeStreamlines(path("paths.xyz"), set), imaging::ImageIoError);
  set.lineValueNames[0] = "a_name_longer_than_19";
  try {
    imaging::writeStreamlines(path("paths.trk"), set);
    ADD_FAILURE() << "no error";
  } catch (const imaging::ImageIoError& e) {
    EXPECT_EQ(std::string(e.what()).rfind(path("paths.trk"), 0), 0u) << e.what();
  }
  EXPECT_TRUE(listFolder(folder()).empty());
  EXPECT_THROW(imaging::writeStreamlines(path("missing_folder/paths.tck"), exampleSet()), imaging::ImageIoError);
}

}  // namespace
}  // namespace stvd::testing
