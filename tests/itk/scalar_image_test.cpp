// Scalar images: reading, writing in the exact geometry, atomic output and
// the geometry comparison.
#include <gtest/gtest.h>

#include <fstream>

#include "stvd/errors.hpp"
#include "stvd/itk/scalar_image_io.hpp"
#include "test_support.hpp"

namespace stvd::imaging {
namespace {

using stvd::testing::HandGeometry;
using stvd::testing::rotation;

GridGeometry obliqueGrid() {
  HandGeometry h;
  h.size = {6, 5, 4};
  h.spacing = {0.8, 1.1, 2.5};
  h.originLps = {101.25, -42.5, 17.75};
  h.directionLps = rotation(-1, 3, 2, 33);
  return h.grid();
}

std::vector<float> ramp(std::size_t n) {
  std::vector<float> values(n);
  for (std::size_t v = 0; v < n; ++v) values[v] = 0.5f * static_cast<float>(v) - 3.f;
  return values;
}

class ScalarImages : public stvd::testing::ScratchFolderTest {};

TEST_F(ScalarImages, WriteAndReadBackInEveryFormatWithTheExactGeometry) {
  const GridGeometry grid = obliqueGrid();
  const std::vector<float> values = ramp(grid.voxelCount());
  for (const std::string name : {"a.nii", "a.nii.gz", "a.nrrd", "a.nhdr"}) {
    SCOPED_TRACE(name);
    writeScalarImage(path(name), grid, values);
    const ScalarImage read = readScalarImage(path(name));
    EXPECT_EQ(read.values, values);
    EXPECT_EQ(read.geometry.size, grid.size);
    // NIfTI stores its geometry in single precision.
    const double tolerance = name.find(".nii") != std::string::npos ? 2e-5 : 1e-12;
    for (int i = 0; i < 3; ++i) {
      EXPECT_NEAR(read.geometry.spacing[i], grid.spacing[i], tolerance * 10);
      EXPECT_NEAR(read.geometry.origin[i], grid.origin[i], tolerance * 100);
    }
    for (int i = 0; i < 9; ++i) EXPECT_NEAR(read.geometry.direction[i], grid.direction[i], tolerance);
    EXPECT_EQ(geometryMismatch(read.geometry, grid), "");
  }
  // Nothing but the outputs (and the detached header's data file).
  const auto files = listFolder(folder());
  for (const auto& f : files) EXPECT_NE(f.rfind(".stvd-staging", 0), 0u) << f;
  EXPECT_EQ(files.size(), 5u);
}

TEST_F(ScalarImages, AFailedWriteLeavesNoFile) {
  const GridGeometry grid = obliqueGrid();
  EXPECT_THROW(writeScalarImage(path("a.png"), grid, ramp(grid.voxelCount())), ImageIoError);
  EXPECT_THROW(writeScalarImage(path("b.nii"), grid, ramp(3)), ImageIoError);
  EXPECT_TRUE(listFolder(folder()).empty());
}

TEST_F(ScalarImages, AnOutputInAMissingFolderIsAnErrorNamingTheFile) {
  const GridGeometry grid = obliqueGrid();
  const std::string file = path("missing/out.nii.gz");
  try {
    writeScalarImage(file, grid, ramp(grid.voxelCount()));
    FAIL() << "no error";
  } catch (const ImageIoError& e) {
    EXPECT_EQ(std::string(e.what()).rfind(file + ": ", 0), 0u) << e.what();
    EXPECT_NE(std::string(e.what()).find("does not exist"), std::string::npos);
  }
  EXPECT_TRUE(listFolder(folder()).empty());
}

TEST_F(ScalarImages, ReadingReportsMissingEmptyAndForeignFiles) {
  std::ofstream(path("empty.nii"));
  std::ofstream(path("text.nii")) << "this is not an image";
  for (const std::string name : {"missing.nii", "empty.nii", "text.nii"}) {
    try {
      readScalarImage(path(name));
      FAIL() << name << ": no error";
    } catch (const ImageIoError& e) {
      EXPECT_EQ(std::string(e.what()).rfind(path(name) + ": ", 0), 0u) << e.what();
    }
  }
}

TEST(GeometryMismatch, NamesTheFirstDifferenceAndAbsorbsSinglePrecision) {
  const GridGeometry a = obliqueGrid();
  GridGeometry b = a;
  b.origin[1] += 1e-6;
  b.spacing[0] *= 1 + 1e-7;
  EXPECT_EQ(geometryMismatch(a, b), "");
  b = a;
  b.size[2] = 7;
  EXPECT_NE(geometryMismatch(a, b).find("size"), std::string::npos);
  b = a;
  b.spacing[1] = 1.2;
  EXPECT_NE(geometryMismatch(a, b).find("spacing"), std::string::npos);
  b = a;
  b.origin[0] += 0.5;
  EXPECT_NE(geometryMismatch(a, b).find("origin"), std::string::npos);
  b = a;
  b.direction = rotation(-1, 3, 2, 34);
  EXPECT_NE(geometryMismatch(a, b).find("direction"), std::string::npos);
}

TEST(ImageExtension, AcceptsTheFourFormatsInAnyCase) {
  EXPECT_TRUE(hasImageExtension("a.nii"));
  EXPECT_TRUE(hasImageExtension("dir.x/a.NII.GZ"));
  EXPECT_TRUE(hasImageExtension("a.nrrd"));
  EXPECT_TRUE(hasImageExtension("a.nhdr"));
  EXPECT_FALSE(hasImageExtension("a.gz"));
  EXPECT_FALSE(hasImageExtension(".nii"));
  EXPECT_FALSE(hasImageExtension("a.vtk"));
}

}  // namespace
}  // namespace stvd::imaging
