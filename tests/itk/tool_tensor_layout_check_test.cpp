// A wrong component order cannot pass unnoticed: read in the wrong order,
// most of a brain's tensors are not positive definite, and stvd stops with
// exit 3 and one line naming the options to check instead of repairing them
// into a plausible-looking map; `stvd info` tries every order.
#include <gtest/gtest.h>

#include <filesystem>

#include "stvd/imaging/tensor_plausibility.hpp"
#include "test_support.hpp"

namespace stvd::testing {
namespace {

namespace fs = std::filesystem;
constexpr int kInput = 3;

class ToolTensorLayoutCheck : public ScratchFolderTest {
 protected:
  /// The shipped six-volume file (FSL order) read in another order.
  std::vector<std::string> sixVolumesAs(const std::string& command, const std::string& order) {
    return {command, sampleFile("dti_tensor_fsl6.nii.gz"), "--tensor-order", order};
  }
};

TEST_F(ToolTensorLayoutCheck, AWrongOrderStopsEveryCommandWithOneLineNamingTheOptions) {
  fs::create_directory(path("out"));
  const std::vector<std::pair<std::string, std::vector<std::string>>> calls{
      {"distance", {"--seed-voxel", "55,54,15", "-o", path("out/d.nii.gz")}},
      {"path", {"--seed-voxel", "55,54,15", "--target-voxel", "62,54,18", "-o", path("out/p.tck")}},
      {"connectivity", {"--labels", sampleFile("dti_mask.nii.gz"), "-o", path("out/c.tsv")}},
  };
  for (const std::string order : {"lower", "mrtrix"})
    for (const auto& [command, options] : calls) {
      std::vector<std::string> arguments = sixVolumesAs(command, order);
      arguments.insert(arguments.end(), options.begin(), options.end());
      const ToolRun run = runTool(arguments);
      EXPECT_EQ(run.exitCode, kInput) << command << " " << order << ": " << run.err;
      EXPECT_EQ(run.err.find('\n'), run.err.size() - 1) << "not one line: " << run.err;
      for (const std::string& named : {sampleFile("dti_tensor_fsl6.nii.gz"), std::string("not positive definite"),
                                      "order " + order, std::string("--tensor-order"), std::string("--tensor-frame"),
                                      std::string("--tensor-kind"), std::string("--accept-implausible-tensors")})
        EXPECT_NE(run.err.find(named), std::string::npos) << command << ": " << named << " missing in " << run.err;
      EXPECT_TRUE(listFolder(path("out")).empty()) << command << " left a file behind";
    }
}

TEST_F(ToolTensorLayoutCheck, TheExplicitFlagAcceptsImplausibleTensors) {
  std::vector<std::string> arguments = sixVolumesAs("distance", "lower");
  for (const std::string a : {"--seed-voxel", "55,54,15", "-o", "", "--accept-implausible-tensors", "-q"})
    arguments.push_back(a.empty() ? path("d.nii.gz") : a);
  const ToolRun run = runTool(arguments);
  EXPECT_EQ(run.exitCode, 0) << run.err;
  EXPECT_TRUE(fs::exists(path("d.nii.gz")));
}

TEST_F(ToolTensorLayoutCheck, TheRightOrdersOfTheSampleFilesPass) {
  for (const auto& [file, order] : std::vector<std::pair<std::string, std::string>>{
           {"dti_tensor_fsl6.nii.gz", "fsl"}, {"dti_tensor_dipy5d.nii.gz", ""}, {"dti_tensor_teem.nrrd", ""}}) {
    std::vector<std::string> arguments{"distance", sampleFile(file), "--seed-voxel", "55,54,15", "-o",
                                       path("d.nii.gz"), "-q"};
    if (!order.empty()) arguments.insert(arguments.end(), {"--tensor-order", order});
    const ToolRun run = runTool(arguments);
    EXPECT_EQ(run.exitCode, 0) << file << ": " << run.err;
  }
}

TEST(ToolInfoOrders, InfoTriesEachOrderAndNamesTheOneThatGivesPositiveDefiniteTensors) {
  const ToolRun run = runTool({"info", sampleFile("dti_tensor_fsl6.nii.gz"), "--tensor-order", "lower"});
  ASSERT_EQ(run.exitCode, 0) << run.err;
  for (const std::string& expected :
       {std::string("Component orders tried"), std::string("lower   xx,xy,yy,xz,yz,zz  18,164 (13.7 %)"),
        std::string("fsl     xx,xy,xz,yy,yz,zz  132,892 (100.0 %)"), std::string("<- as read"),
        std::string("86.3 % of the tensors are not positive definite"), std::string("try --tensor-order fsl")})
    EXPECT_NE(run.out.find(expected), std::string::npos) << expected << " missing in\n" << run.out;
  // Read right, no warning.
  const ToolRun right = runTool({"info", sampleFile("dti_tensor_fsl6.nii.gz"), "--tensor-order", "fsl"});
  ASSERT_EQ(right.exitCode, 0) << right.err;
  EXPECT_EQ(right.out.find("Warning"), std::string::npos) << right.out;
}

TEST(TensorPlausibility, MoreThanATenthNotPositiveDefiniteIsImplausible) {
  imaging::MetricVoxelCounts counts;
  counts.total = 1200;
  counts.zero = 200;  // 1000 tensors with a value
  counts.notPositiveDefinite = 100;
  EXPECT_EQ(imaging::implausibleTensorsReason(counts), "");
  counts.notPositiveDefinite = 101;
  counts.faAboveOne = 60;
  EXPECT_EQ(imaging::implausibleTensorsReason(counts),
            "101 of its 1,000 tensors (10.1 %) are not positive definite (60 with FA above 1)");
}

}  // namespace
}  // namespace stvd::testing
