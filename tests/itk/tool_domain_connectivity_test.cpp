// `--domain-connectivity 6|18|26` through the real executable: which domain
// voxels touch, for every method and for `stvd path` and `stvd
// connectivity`, on a hand-written masked file whose distances are worked
// out by hand.
#include <gtest/gtest.h>

#include <cmath>
#include <fstream>
#include <sstream>

#include "stvd/itk/scalar_image_io.hpp"
#include "test_support.hpp"

namespace stvd::testing {
namespace {

/// 20 x 20 x 3 voxels of 1 mm, the identity metric, and a mask with a
/// diagonal wall (i, i, k), i = 0..14, and a pocket: the column (18, 1, k),
/// whose four neighbours in the plane are masked, so that it touches the
/// rest of the domain only along edges; so does the column (19, 0, k) in the
/// image's corner next to it.
///
/// From (12, 4, 1) to (4, 12, 1): with connectivity 6 the way runs around
/// the wall's end, over the corners (15, 13), (15, 15) and (13, 15) of the
/// removed squares (i - 1, i + 1)^2: 2 sqrt(3^2 + 9^2) + 4 = 22.97 mm. With
/// 18 (or 26) the wall is crossed between (9, 8) and (8, 9):
/// 5 + sqrt(2) + 5 = 11.41 mm.
class ToolDomainConnectivity : public ScratchFolderTest {
 protected:
  static constexpr int kN = 20, kLayers = 3;
  const double kAround = 2.0 * std::sqrt(90.0) + 4.0;
  const double kAcross = 10.0 + std::sqrt(2.0);

  void SetUp() override {
    ScratchFolderTest::SetUp();
    geometry_.size = {kN, kN, kLayers};
    writeTensorNrrdByHand(path("slab.nrrd"), geometry_, "left-posterior-superior",
                          std::vector<SymTensor3>(kN * kN * kLayers, SymTensor3{1, 0, 0, 1, 0, 1}), nullptr);
    std::vector<float> mask(kN * kN * kLayers, 1.f);
    for (int k = 0; k < kLayers; ++k) {
      for (int i = 0; i <= 14; ++i) mask[linear(i, i, k)] = 0.f;
      for (const auto& p : {std::array<int, 2>{17, 1}, {19, 1}, {18, 0}, {18, 2}}) mask[linear(p[0], p[1], k)] = 0.f;
    }
    writeScalarNiftiByHand(path("mask.nii"), geometry_, mask);
    std::vector<float> labels(kN * kN * kLayers, 0.f);
    labels[linear(12, 4, 1)] = 1.f;
    labels[linear(4, 12, 1)] = 2.f;
    writeScalarNiftiByHand(path("labels.nii"), geometry_, labels);
  }

  static std::size_t linear(int i, int j, int k) { return i + kN * (j + kN * std::size_t(k)); }

  ToolRun distance(const std::vector<std::string>& options, const std::string& out) {
    std::vector<std::string> args{"distance", path("slab.nrrd"), "--tensor-kind", "metric", "--mask", path("mask.nii"),
                                  "--seed-voxel", "12,4,1", "-o", path(out)};
    args.insert(args.end(), options.begin(), options.end());
    return runTool(args);
  }

  HandGeometry geometry_;
};

TEST_F(ToolDomainConnectivity, EveryMethodReachesTheSameVoxelsAndKeepsToTheRegion) {
  const std::vector<std::vector<std::string>> methods{
      {"--method", "dijkstra"}, {}, {"--method", "lanthier", "--steiner", "2"}};
  for (const std::string connectivity : {"6", "18", "26"}) {
    for (const auto& method : methods) {
      std::vector<std::string> options = method;
      options.insert(options.end(), {"--domain-connectivity", connectivity});
      const ToolRun run = distance(options, "d.nii.gz");
      ASSERT_EQ(run.exitCode, 0) << run.err;
      // The two columns (6 voxels) touch the rest along edges only.
      const std::string reached = connectivity == "6" ? "Reached 1,137 of 1,143" : "Reached 1,143 of 1,143";
      EXPECT_NE(run.out.find(reached), std::string::npos) << connectivity << ": " << run.out;
      EXPECT_NE(run.out.find("domain connectivity " + connectivity), std::string::npos) << run.out;
      const imaging::ScalarImage d = imaging::readScalarImage(path("d.nii.gz"));
      const double target = d.values[linear(4, 12, 1)];
      if (connectivity == "6") {
        EXPECT_GE(target, kAround * (1.0 - 2e-6)) << "through the diagonal wall: " << run.out;
      } else {
        EXPECT_GE(target, kAcross * (1.0 - 2e-6)) << run.out;
        EXPECT_LT(target, kAround) << "the edge contacts were not used: " << run.out;
      }
    }
  }
}

TEST_F(ToolDomainConnectivity, IsInTheStatisticsAndDefaultsToSix) {
  ASSERT_EQ(distance({"--stats", path("a.json"), "-q"}, "a.nii.gz").exitCode, 0);
  ASSERT_EQ(distance({"--stats", path("b.json"), "-q", "--domain-connectivity", "26"}, "b.nii.gz").exitCode, 0);
  for (const auto& [file, value] : {std::pair<std::string, std::string>{"a.json", "6"}, {"b.json", "26"}}) {
    std::ifstream in(path(file));
    std::stringstream json;
    json << in.rdbuf();
    EXPECT_NE(json.str().find("\"domain_connectivity\": " + value + ","), std::string::npos) << json.str();
  }
}

TEST_F(ToolDomainConnectivity, PathsAndConnectivityUseIt) {
  for (const std::string connectivity : {"6", "18"}) {
    const ToolRun path_ = runTool({"path", path("slab.nrrd"), "--tensor-kind", "metric", "--mask", path("mask.nii"),
                                   "--seed-voxel", "12,4,1", "--target-voxel", "4,12,1", "-o", path("p.tck"),
                                   "--domain-connectivity", connectivity});
    ASSERT_EQ(path_.exitCode, 0) << path_.err;
    EXPECT_NE(path_.out.find("domain connectivity " + connectivity), std::string::npos) << path_.out;
    const auto rows = readTsv(path("p.tsv"));
    ASSERT_EQ(rows.size(), 1u);
    const double geodesic = std::stod(rows[0].at("geodesic_mm"));
    const ToolRun table = runTool({"connectivity", path("slab.nrrd"), "--tensor-kind", "metric", "--mask",
                                   path("mask.nii"), "--labels", path("labels.nii"), "-o", path("t.tsv"),
                                   "--domain-connectivity", connectivity, "--threads", "1"});
    ASSERT_EQ(table.exitCode, 0) << table.err;
    const auto pairs = readTsv(path("t.tsv"));
    ASSERT_EQ(pairs.size(), 2u);
    for (const double d : {geodesic, std::stod(pairs[0].at("geodesic_mm"))}) {
      if (connectivity == "6") {
        EXPECT_GE(d, kAround * (1.0 - 1e-4));
      } else {
        EXPECT_GE(d, kAcross * (1.0 - 1e-4));
        EXPECT_LT(d, kAround);
      }
    }
  }
}

TEST_F(ToolDomainConnectivity, CommandLineRulesAreExplained) {
  auto expectUsageError = [&](const std::vector<std::string>& options, const std::string& mentioned) {
    const ToolRun run = distance(options, "never.nii.gz");
    EXPECT_EQ(run.exitCode, 2) << run.err;
    EXPECT_EQ(run.err.find('\n'), run.err.size() - 1) << run.err;
    EXPECT_NE(run.err.find(mentioned), std::string::npos) << run.err;
    EXPECT_FALSE(std::ifstream(path("never.nii.gz")).good());
  };
  expectUsageError({"--domain-connectivity", "8"}, "not one of 6, 18, 26");
  // Every method must reach the same voxels: the stencil must step across
  // the contacts that the connectivity joins.
  expectUsageError({"--stencil", "6", "--domain-connectivity", "18"}, "--stencil 18 or larger");
  expectUsageError({"--stencil", "18", "--domain-connectivity", "26"}, "--stencil 26 or larger");
  EXPECT_EQ(distance({"--stencil", "98", "--domain-connectivity", "26", "-q"}, "d.nii.gz").exitCode, 0);
  // Surfaces have no voxels.
  {
    std::ofstream obj(path("t.obj"));
    obj << "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n";
  }
  const ToolRun surface = runTool(
      {"distance", path("t.obj"), "--seed-vertex", "0", "-o", path("t.csv"), "--domain-connectivity", "18"});
  EXPECT_EQ(surface.exitCode, 2) << surface.err;
  EXPECT_NE(surface.err.find("--domain-connectivity applies to voxel grids only"), std::string::npos) << surface.err;
}

}  // namespace
}  // namespace stvd::testing
