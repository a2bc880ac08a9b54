// Distance maps as OpenVDB grids: active where reached, placed in RAS
// millimetres by the grid's transform.
#include <gtest/gtest.h>

#include <openvdb/openvdb.h>

#include <cmath>
#include <limits>

#include "stvd/imaging/tensor_volume.hpp"
#include "stvd/vdb/distance_grid.hpp"
#include "test_support.hpp"

namespace stvd::testing {
namespace {

openvdb::FloatGrid::Ptr readGrid(const std::string& path) {
  openvdb::initialize();
  openvdb::io::File file(path);
  file.open();
  openvdb::GridBase::Ptr base = file.readGrid("distance");
  file.close();
  return openvdb::gridPtrCast<openvdb::FloatGrid>(base);
}

class VdbOutput : public ScratchFolderTest {};

TEST_F(VdbOutput, ReachedVoxelsAreActiveAndPlacedInRasMillimetres) {
  HandGeometry h;
  h.size = {4, 3, 2};
  h.spacing = {0.5, 1.5, 3.0};
  h.originLps = {10.0, -20.0, 30.0};
  h.directionLps = rotation(2, -1, 1, 40);
  const GridGeometry g = h.grid();
  std::vector<double> distance(g.voxelCount());
  for (std::size_t v = 0; v < distance.size(); ++v) distance[v] = 0.25 * double(v);
  distance[5] = std::numeric_limits<double>::infinity();
  distance[17] = std::numeric_limits<double>::quiet_NaN();
  vdb::writeDistanceGrid(path("d.vdb"), g, distance, {"distance", -1.f});
  EXPECT_EQ(listFolder(folder()), std::vector<std::string>{"d.vdb"});

  const openvdb::FloatGrid::Ptr grid = readGrid(path("d.vdb"));
  ASSERT_TRUE(grid);
  EXPECT_EQ(grid->activeVoxelCount(), openvdb::Index64(distance.size() - 2));
  EXPECT_EQ(grid->background(), -1.f);
  EXPECT_EQ(grid->metaValue<std::string>("world_frame"), "RAS");
  EXPECT_EQ(grid->metaValue<std::string>("units"), "mm");
  const auto accessor = grid->getConstAccessor();
  for (int k = 0; k < 2; ++k)
    for (int j = 0; j < 3; ++j)
      for (int i = 0; i < 4; ++i) {
        const std::size_t v = std::size_t(i) + 4 * (std::size_t(j) + 3 * std::size_t(k));
        const openvdb::Coord ijk(i, j, k);
        EXPECT_EQ(accessor.isValueOn(ijk), std::isfinite(distance[v])) << v;
        if (std::isfinite(distance[v])) {
          EXPECT_FLOAT_EQ(accessor.getValue(ijk), float(distance[v]));
        }
        const openvdb::Vec3d world = grid->indexToWorld(openvdb::Vec3d(i, j, k));
        const Vec3d lps = g.indexToPhysicalPoint(i, j, k);
        EXPECT_NEAR(world.x(), -lps.x, 1e-9);
        EXPECT_NEAR(world.y(), -lps.y, 1e-9);
        EXPECT_NEAR(world.z(), lps.z, 1e-9);
      }
}

TEST_F(VdbOutput, TheToolWritesTheBrainsDistanceMapAsAGrid) {
  const ToolRun run = runTool({"distance", sampleFile("dti_tensor_dipy5d.nii.gz"), "--seed-voxel", "55,54,15", "-o",
                               path("cc_body.vdb")});
  ASSERT_EQ(run.exitCode, 0) << run.err;
  EXPECT_NE(run.out.find("OpenVDB FloatGrid"), std::string::npos);
  const openvdb::FloatGrid::Ptr grid = readGrid(path("cc_body.vdb"));
  ASSERT_TRUE(grid);
  EXPECT_EQ(grid->activeVoxelCount(), 132892u);
  EXPECT_EQ(grid->getConstAccessor().getValue(openvdb::Coord(55, 54, 15)), 0.f);
  // The seed lands where seeds.tsv puts CC_body: RAS (6.39, 11.57, 76.31) mm.
  const openvdb::Vec3d seed = grid->indexToWorld(openvdb::Vec3d(55, 54, 15));
  EXPECT_NEAR(seed.x(), 6.39, 0.01);
  EXPECT_NEAR(seed.y(), 11.57, 0.01);
  EXPECT_NEAR(seed.z(), 76.31, 0.01);
}

TEST_F(VdbOutput, AMissingFolderIsAnErrorAndLeavesNothing) {
  const ToolRun run = runTool({"distance", sampleFile("dti_tensor_dipy5d.nii.gz"), "--seed-voxel", "55,54,15", "-o",
                               path("missing/cc_body.vdb")});
  EXPECT_EQ(run.exitCode, 5);
  EXPECT_NE(run.err.find("does not exist"), std::string::npos) << run.err;
  EXPECT_TRUE(listFolder(folder()).empty());
}

}  // namespace
}  // namespace stvd::testing
