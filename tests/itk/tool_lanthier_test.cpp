// `stvd distance --method lanthier --steiner M` through the real executable:
// exact distances from a hand-written oblique file with a constant metric,
// the parameters in the statistics file, and the command-line rules.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <fstream>
#include <sstream>

#include "known_field.hpp"
#include "stvd/itk/scalar_image_io.hpp"
#include "test_support.hpp"

namespace stvd::testing {
namespace {

class ToolLanthier : public ScratchFolderTest {
 protected:
  void SetUp() override {
    ScratchFolderTest::SetUp();
    const Matrix3 frame = field_.measurementFrameLps;
    writeTensorNrrdByHand(path("field.nrrd"), field_.geometry, "left-posterior-superior",
                          std::vector<SymTensor3>(field_.voxelCount(), field_.measurementFrameMetric()), &frame);
  }

  /// Mean relative error over all voxels (the centre is the seed) and the
  /// most negative one.
  struct Errors {
    double mean = 0.0, minSigned = 0.0;
  };
  Errors errorsFrom(const std::vector<std::string>& method, const std::string& out) {
    std::vector<std::string> args{"distance", path("field.nrrd"), "-o", path(out), "--tensor-kind", "metric",
                                  "--seed-voxel", "5,4,3", "-q"};
    args.insert(args.end(), method.begin(), method.end());
    const ToolRun run = runTool(args);
    EXPECT_EQ(run.exitCode, 0) << run.err;
    const imaging::ScalarImage d = imaging::readScalarImage(path(out));
    Errors e;
    std::size_t n = 0;
    for (int k = 0; k < field_.geometry.size[2]; ++k)
      for (int j = 0; j < field_.geometry.size[1]; ++j)
        for (int i = 0; i < field_.geometry.size[0]; ++i) {
          const std::array<int, 3> p{i, j, k};
          if (p == field_.centre()) continue;
          const double exact = field_.exactDistance(field_.centre(), p);
          const double relative = (d.values[field_.linear(p)] - exact) / exact;
          e.mean += std::abs(relative);
          e.minSigned = std::min(e.minSigned, relative);
          ++n;
        }
    e.mean /= double(n);
    return e;
  }

  void expectUsageError(const std::vector<std::string>& options, const std::string& mentioned) {
    std::vector<std::string> args{"distance", path("field.nrrd"), "-o", path("never.nii.gz"), "--tensor-kind",
                                  "metric", "--seed-voxel", "5,4,3"};
    args.insert(args.end(), options.begin(), options.end());
    const ToolRun run = runTool(args);
    EXPECT_EQ(run.exitCode, 2) << run.err;
    EXPECT_EQ(run.out, "");
    EXPECT_EQ(run.err.find('\n'), run.err.size() - 1) << run.err;
    EXPECT_NE(run.err.find(mentioned), std::string::npos) << run.err;
    EXPECT_FALSE(std::ifstream(path("never.nii.gz")).good());
  }

  KnownField field_;
};

TEST_F(ToolLanthier, DistancesAtVoxelsConvergeToTheExactOnesFromAbove) {
  // Measured (Release, x86-64): mean relative error 0.0155 with M = 1,
  // 0.00327 with M = 4, against Dijkstra's 0.0767 on the 26-neighbourhood.
  const Errors dijkstra = errorsFrom({"--method", "dijkstra"}, "dijkstra.nii.gz");
  const Errors coarse = errorsFrom({"--method", "lanthier", "--steiner", "1"}, "m1.nii.gz");
  const Errors fine = errorsFrom({"--method", "lanthier", "--steiner", "4"}, "m4.nii.gz");
  std::printf("[ measured ] tool, constant metric: Dijkstra %.5f, lanthier M = 1 %.5f, M = 4 %.5f\n",
              dijkstra.mean, coarse.mean, fine.mean);
  EXPECT_LT(fine.mean, coarse.mean);
  EXPECT_LT(coarse.mean, dijkstra.mean);
  EXPECT_LE(fine.mean, 0.0046);
  // A constant metric on a box: no Steiner path is shorter than the
  // straight line (float32 output: 1e-6 relative).
  EXPECT_GE(fine.minSigned, -2e-6);
  EXPECT_GE(coarse.minSigned, -2e-6);
}

TEST_F(ToolLanthier, StatsAndSummaryNameTheMethodAndItsSteinerPoints) {
  const ToolRun run = runTool({"distance", path("field.nrrd"), "-o", path("d.nrrd"), "--tensor-kind", "metric",
                               "--seed-voxel", "5,4,3", "--method", "lanthier", "--steiner", "2", "--stats",
                               path("d.json")});
  ASSERT_EQ(run.exitCode, 0) << run.err;
  EXPECT_NE(run.out.find("Method: Lanthier Steiner-point propagation with M = 2 points per cube edge."),
            std::string::npos) << run.out;
  std::ifstream in(path("d.json"));
  std::stringstream json;
  json << in.rdbuf();
  EXPECT_NE(json.str().find("\"method\": \"lanthier\""), std::string::npos) << json.str();
  EXPECT_NE(json.str().find("\"steiner_points\": 2"), std::string::npos) << json.str();
  EXPECT_NE(json.str().find("\"k\": null"), std::string::npos) << json.str();
  // Cells, not stencil edges or chains: those parameters do not apply.
  EXPECT_EQ(json.str().find("\"chain_measure\""), std::string::npos) << json.str();
  EXPECT_EQ(json.str().find("\"stencil\""), std::string::npos) << json.str();
}

TEST_F(ToolLanthier, CommandLineRulesAreExplained) {
  expectUsageError({"--method", "lanthier"}, "--steiner");
  expectUsageError({"--method", "lanthier", "--steiner", "0"}, "between 1 and 16");
  expectUsageError({"--method", "lanthier", "--steiner", "17"}, "between 1 and 16");
  expectUsageError({"--method", "lanthier", "--steiner", "two"}, "--steiner");
  expectUsageError({"--steiner", "2"}, "--method lanthier only");
  expectUsageError({"--method", "lanthier", "--steiner", "2", "--k", "5"}, "--k");
  expectUsageError({"--method", "lanthier", "--steiner", "2", "--stencil", "6"}, "--stencil");
}

TEST_F(ToolLanthier, ASingleSliceIsPropagatedThroughItsSquares) {
  // One slice has no cubes: its squares are the cells, as for Dijkstra and
  // STVD every voxel is reached, and no distance is below the straight line.
  KnownField slice;
  slice.geometry.size = {11, 9, 1};
  const Matrix3 frame = slice.measurementFrameLps;
  writeTensorNrrdByHand(path("slice.nrrd"), slice.geometry, "left-posterior-superior",
                        std::vector<SymTensor3>(slice.voxelCount(), slice.measurementFrameMetric()), &frame);
  const ToolRun run = runTool({"distance", path("slice.nrrd"), "-o", path("slice.nii.gz"), "--tensor-kind",
                               "metric", "--seed-voxel", "5,4,0", "--method", "lanthier", "--steiner", "2"});
  ASSERT_EQ(run.exitCode, 0) << run.err;
  EXPECT_NE(run.out.find("Reached 99 of 99 domain voxels"), std::string::npos) << run.out;
  const imaging::ScalarImage d = imaging::readScalarImage(path("slice.nii.gz"));
  double worst = 0.0;
  for (int j = 0; j < 9; ++j)
    for (int i = 0; i < 11; ++i) {
      if (i == 5 && j == 4) continue;
      const double exact = slice.exactDistance({5, 4, 0}, {i, j, 0});
      const double value = d.values[slice.linear({i, j, 0})];
      EXPECT_GE(value, exact * (1.0 - 2e-6)) << i << " " << j;
      worst = std::max(worst, value / exact - 1.0);
    }
  // Measured: at most 6.6 % above at M = 2, next to the seed.
  EXPECT_LT(worst, 0.09);
}

}  // namespace
}  // namespace stvd::testing
