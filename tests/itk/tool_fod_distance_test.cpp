// `stvd distance FOD --fod-basis NAME` (docs/fod.md, "The tool"): a crossing
// written as an FOD image by the test, through the tool. Two bundles, 5
// voxels wide, cross at 90 degrees in the middle of a 25 x 25 x 3 grid; each
// voxel's FOD (lmax 8, tournier07 in DIPY's voxel frame) has one lobe per
// bundle it lies in, none outside. The map the tool writes has the far end
// of the seed's own bundle at the bundle's length, the other bundle's far
// end at the two legs' length, the input's grid, and the same bytes on 1
// and 2 threads; wrong bases, FOD images without a basis and tensor images
// with one are refused in one line with nothing written.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "fod_crossing.hpp"
#include "stvd/imaging/fod_cost.hpp"
#include "stvd/imaging/fod_segment_norm.hpp"
#include "stvd/itk/fod_volume_io.hpp"
#include "stvd/itk/scalar_image_io.hpp"
#include "stvd/voxel_grid/stencil.hpp"
#include "stvd/voxel_grid/voxel_grid_domain.hpp"
#include "stvd/voxel_grid/voxel_grid_lanthier.hpp"
#include "stvd/voxel_grid/voxel_grid_propagation.hpp"
#include "test_support.hpp"

namespace stvd::testing {
namespace {

constexpr int kN = kCrossingSize, kC = kCrossingCentre, kHalfWidth = kCrossingHalfWidth;

std::string fileText(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  std::ostringstream s;
  s << in.rdbuf();
  return s.str();
}

class ToolFodDistance : public ScratchFolderTest {
 protected:
  void SetUp() override {
    ScratchFolderTest::SetUp();
    writeFodCrossing(path("fod.nii"));  // 90 degrees: bundle 0 along i, bundle 1 along j
  }

  ToolRun distance(const std::vector<std::string>& extra) const {
    std::vector<std::string> arguments{"distance", path("fod.nii"), "-q", "--seed-voxel", "0,12,1"};
    arguments.insert(arguments.end(), extra.begin(), extra.end());
    return runTool(arguments);
  }

  /// A refused run: exit code `code`, one line on stderr holding `words`, no output.
  void expectRefused(const std::vector<std::string>& arguments, int code, const std::string& words) const {
    const ToolRun r = runTool(arguments);
    EXPECT_EQ(r.exitCode, code) << r.err;
    EXPECT_NE(r.err.find(words), std::string::npos) << r.err;
    EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << r.err;
    EXPECT_FALSE(std::filesystem::exists(path("refused.nii")));
  }
};

// STVD is the default, as for tensors (docs/fod.md, "The tool"); Dijkstra
// is kept on request (and for paths and connectivity): each reaches the
// seed's own bundle's far end at its length and the other bundle's far end
// along both bundles, and the statistics name the method and its table.
TEST_F(ToolFodDistance, TheSeedsOwnBundleIsReachedAtItsLengthOnTheInputsGrid) {
  struct Run {
    std::vector<std::string> method;
    const char* name;
    const char* table;
  };
  for (const Run& run : {Run{{}, "stvd", "lattice directions of order 2"},
                         Run{{"--method", "dijkstra"}, "dijkstra", "the 26 neighbour directions"}}) {
    std::vector<std::string> arguments{"--fod-basis", "tournier07", "-o", path("d.nii"), "--stats", path("d.json")};
    arguments.insert(arguments.end(), run.method.begin(), run.method.end());
    const ToolRun r = distance(arguments);
    ASSERT_EQ(r.exitCode, 0) << r.err;
    const imaging::ScalarImage map = imaging::readScalarImage(path("d.nii"));
    const GridGeometry input = HandGeometry{{kN, kN, 3}}.grid();
    ASSERT_EQ(map.geometry.size, input.size);
    for (int a = 0; a < 3; ++a) {
      EXPECT_DOUBLE_EQ(map.geometry.spacing[a], input.spacing[a]);
      EXPECT_NEAR(map.geometry.origin[a], input.origin[a], 1e-9);
    }
    const auto at = [&](int i, int j, int k) { return map.values[i + kN * (j + kN * k)]; };
    EXPECT_EQ(at(0, kC, 1), 0.f);
    // Along its own bundle, straight through the crossing: 24 mm at 1 per mm.
    EXPECT_NEAR(at(kN - 1, kC, 1), 24.0, 24e-3) << run.name;
    // The other bundle's far end: along bundle 0 to the crossing, then along bundle 1.
    EXPECT_NEAR(at(kC, kN - 1, 1), 24.0, 0.02 * 24.0) << run.name;
    // A voxel of neither bundle costs the floor's 10 per mm to reach across.
    EXPECT_GT(at(kN - 1, kN - 1, 1), at(kC, kN - 1, 1) + 20.0) << run.name;

    const std::string stats = fileText(path("d.json"));
    const std::string method = std::string("\"method\": \"") + run.name + "\"";
    for (const std::string& member : {std::string("\"metric\": \"fod\""), std::string("\"fod_basis\": \"tournier07\""),
                                      std::string("\"fod_frame\": \"voxel\""), std::string("\"fod_lmax\": 8"),
                                      std::string("\"fod_floor\": 0.1"), std::string("\"fod_power\": 1"),
                                      std::string("\"fod_directions\": 668"), method, std::string(run.table),
                                      std::string("\"fod_precomputation\": {\"seconds\": "),
                                      std::string("\"cpu_seconds\": ")})
      EXPECT_NE(stats.find(member), std::string::npos) << member << "\n" << stats;
  }
}

// The default is --method stvd, byte for byte, and takes --k as STVD does;
// it is not Dijkstra's map. (Before, Dijkstra was the FOD default and --k
// without --method was refused.)
TEST_F(ToolFodDistance, StvdIsTheDefaultAsForTensors) {
  ASSERT_EQ(distance({"--fod-basis", "tournier07", "-o", path("default.nii")}).exitCode, 0);
  ASSERT_EQ(distance({"--fod-basis", "tournier07", "--method", "stvd", "-o", path("stvd.nii")}).exitCode, 0);
  ASSERT_EQ(distance({"--fod-basis", "tournier07", "--method", "dijkstra", "-o", path("dijkstra.nii")}).exitCode, 0);
  const std::string byDefault = fileText(path("default.nii"));
  ASSERT_FALSE(byDefault.empty());
  EXPECT_EQ(byDefault, fileText(path("stvd.nii")));
  EXPECT_NE(byDefault, fileText(path("dijkstra.nii")));
  const ToolRun k =
      distance({"--fod-basis", "tournier07", "--k", "8", "-o", path("k8.nii"), "--stats", path("k8.json")});
  ASSERT_EQ(k.exitCode, 0) << k.err;
  EXPECT_NE(fileText(path("k8.json")).find("\"method\": \"stvd\""), std::string::npos);
}

// STVD and Lanthier's method run on the segment norm (docs/fod.md, "STVD and
// Lanthier"): the tool's map is the library's run on the same file, value for
// value, and the seed's own bundle is reached at its length.
TEST_F(ToolFodDistance, StvdAndLanthierGiveTheLibrarysMap) {
  imaging::FodReadOptions read;
  read.basis = "tournier07";
  const imaging::FodField field = imaging::readFodVolume(path("fod.nii"), read);
  const imaging::FodCostSampler sampler(field, imaging::defaultFodSampling(field.geometry));
  const imaging::FodSegmentMetric metric = imaging::fodSegmentMetric(sampler);
  const VoxelGridDomain domain(field.geometry, Stencil::full26());
  const VertexId seed = domain.vertexAt(0, kC, 1);
  for (const std::string method : {"stvd", "lanthier"}) {
    std::vector<std::string> arguments{"--fod-basis", "tournier07", "--method", method, "-o", path(method + ".nii"),
                                       "--stats", path(method + ".json")};
    if (method == "lanthier") arguments.insert(arguments.end(), {"--steiner", "3"});
    const ToolRun r = distance(arguments);
    ASSERT_EQ(r.exitCode, 0) << r.err;
    std::vector<double> expected;
    if (method == "stvd") {
      expected = propagate(domain, metric, {seed}).distance;
    } else {
      LanthierOptions steiner;
      steiner.steinerPoints = 3;
      expected = lanthierPropagate(domain, metric, {seed}, steiner).distance;
    }
    const imaging::ScalarImage map = imaging::readScalarImage(path(method + ".nii"));
    ASSERT_EQ(map.values.size(), expected.size());
    std::size_t differing = 0;
    for (std::size_t v = 0; v < expected.size(); ++v) differing += map.values[v] != static_cast<float>(expected[v]);
    EXPECT_EQ(differing, 0u) << method;
    // Along its own bundle, through the crossing: 24 mm at 1 per mm.
    EXPECT_NEAR(map.values[(kN - 1) + kN * (kC + kN)], 24.0, 24e-3) << method;
    const std::string stats = fileText(path(method + ".json"));
    EXPECT_NE(stats.find("\"method\": \"" + method + "\""), std::string::npos) << stats;
    EXPECT_NE(stats.find("lattice directions of order 2"), std::string::npos) << stats;
  }
}

TEST_F(ToolFodDistance, TheMapIsTheSameOnOneAndTwoThreads) {
  ASSERT_EQ(distance({"--fod-basis", "tournier07", "--threads", "1", "-o", path("one.nii")}).exitCode, 0);
  ASSERT_EQ(distance({"--fod-basis", "tournier07", "--threads", "2", "-o", path("two.nii")}).exitCode, 0);
  const std::string one = fileText(path("one.nii")), two = fileText(path("two.nii"));
  ASSERT_FALSE(one.empty());
  EXPECT_EQ(one, two);
}

TEST_F(ToolFodDistance, FloorAndPowerChangeTheCost) {
  // A higher floor makes leaving the bundles cheaper: the corner is nearer.
  ASSERT_EQ(distance({"--fod-basis", "tournier07", "-o", path("d.nii")}).exitCode, 0);
  ASSERT_EQ(distance({"--fod-basis", "tournier07", "--fod-floor", "0.5", "--fod-power", "1", "-o", path("f.nii")})
                .exitCode,
            0);
  const auto corner = [&](const std::string& name) {
    return imaging::readScalarImage(path(name)).values[(kN - 1) + kN * ((kN - 1) + kN * 1)];
  };
  EXPECT_LT(corner("f.nii"), corner("d.nii") - 10.0);
}

TEST_F(ToolFodDistance, AMaskKeepsTheRunInsideItsVoxelsAndASeedPointFindsItsVoxel) {
  // The mask is bundle 0 only: its far end is reached as before, bundle 1's
  // is not reached (the unreachable value), and a seed outside it is refused.
  HandGeometry g;
  g.size = {kN, kN, 3};
  std::vector<float> mask(std::size_t(kN) * kN * 3, 0.f);
  for (int k = 0; k < 3; ++k)
    for (int j = kC - kHalfWidth; j <= kC + kHalfWidth; ++j)
      for (int i = 0; i < kN; ++i) mask[i + kN * (j + kN * k)] = 1.f;
  writeScalarNiftiByHand(path("mask.nii"), g, mask);
  // Voxel (0, 12, 1) is at LPS (0, 12, 1): RAS (0, -12, 1).
  const ToolRun r = runTool({"distance", path("fod.nii"), "-q", "--fod-basis", "tournier07", "--seed-point", "0,-12,1",
                             "--mask", path("mask.nii"), "-o", path("m.nii")});
  ASSERT_EQ(r.exitCode, 0) << r.err;
  const imaging::ScalarImage map = imaging::readScalarImage(path("m.nii"));
  const auto at = [&](int i, int j, int k) { return map.values[i + kN * (j + kN * k)]; };
  EXPECT_EQ(at(0, kC, 1), 0.f);
  EXPECT_NEAR(at(kN - 1, kC, 1), 24.0, 24e-3);
  EXPECT_EQ(at(kC, kN - 1, 1), -1.f);
  expectRefused({"distance", path("fod.nii"), "--fod-basis", "tournier07", "--seed-voxel", "12,24,1", "--mask",
                 path("mask.nii"), "-o", path("refused.nii")},
                4, "outside the mask");
}

TEST_F(ToolFodDistance, BadInputsAreRefusedInOneLineWithNothingWritten) {
  const std::string fod = path("fod.nii"), out = path("refused.nii");
  expectRefused({"distance", fod, "--fod-basis", "tournier08", "--seed-voxel", "0,12,1", "-o", out}, 2,
                "--fod-basis");
  // An FOD image without its basis: the tensor reader refuses it, the tool says what it is.
  expectRefused({"distance", fod, "--seed-voxel", "0,12,1", "-o", out}, 3, "state its basis with --fod-basis");
  // --k goes with STVD (the default), not with Dijkstra; Lanthier needs its M.
  expectRefused({"distance", fod, "--fod-basis", "tournier07", "--method", "dijkstra", "--k", "8", "--seed-voxel",
                 "0,12,1", "-o", out},
                2, "--k applies to --method stvd only");
  expectRefused({"distance", fod, "--fod-basis", "tournier07", "--method", "lanthier", "--seed-voxel", "0,12,1",
                 "-o", out},
                2, "needs --steiner");
  expectRefused({"distance", fod, "--fod-floor", "0.2", "--seed-voxel", "0,12,1", "-o", out}, 2,
                "--fod-floor applies to FOD images");
  expectRefused({"distance", fod, "--fod-basis", "tournier07", "--tensor-order", "fsl", "--seed-voxel", "0,12,1",
                 "-o", out},
                2, "--tensor-order applies to tensor images");
  expectRefused({"distance", fod, "--fod-basis", "tournier07", "--seed-voxel", "30,12,1", "-o", out}, 4,
                "outside the image");

  // A tensor image given with --fod-basis: six volumes are no FOD.
  HandGeometry g;
  g.size = {3, 3, 3};
  writeNiftiByHand(path("t6.nii"), g, NiftiTensorLayout::SixVolumes4D,
                   std::vector<std::array<float, 6>>(27, {1, 0, 0, 1, 0, 1}));
  expectRefused({"distance", path("t6.nii"), "--fod-basis", "tournier07", "--seed-voxel", "1,1,1", "-o", out}, 3,
                "a tensor image's");
  writeNiftiByHand(path("t5.nii"), g, NiftiTensorLayout::SymMatrix5D,
                   std::vector<std::array<float, 6>>(27, {1, 0, 0, 1, 0, 1}));
  expectRefused({"distance", path("t5.nii"), "--fod-basis", "tournier07", "--seed-voxel", "1,1,1", "-o", out}, 3,
                path("t5.nii"));
}

}  // namespace
}  // namespace stvd::testing
