// Every bad input gives one line on stderr naming the file and the problem,
// its documented exit code, and no output file.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>

#include "known_field.hpp"
#include "stvd/itk/scalar_image_io.hpp"
#include "stvd/imaging/tensor_volume.hpp"
#include "test_support.hpp"

namespace stvd::testing {
namespace {

namespace fs = std::filesystem;

constexpr int kUsage = 2, kInput = 3, kDomain = 4, kOutput = 5;

class ToolBadInput : public ScratchFolderTest {
 protected:
  void SetUp() override {
    ScratchFolderTest::SetUp();
    fs::create_directory(path("in"));
    fs::create_directory(path("out"));
  }
  std::string input(const std::string& name) const { return path("in/" + name); }
  std::string output(const std::string& name = "distance.nii.gz") const { return path("out/" + name); }

  /// Runs `stvd distance` and checks the failure: exit code, one stderr
  /// line that mentions `mentioned`, nothing on stdout, nothing written.
  void expectFailure(const std::vector<std::string>& arguments, int exitCode, const std::string& mentioned,
                     const std::string& problem = "") {
    std::vector<std::string> all{"distance"};
    all.insert(all.end(), arguments.begin(), arguments.end());
    const ToolRun run = runTool(all);
    EXPECT_EQ(run.exitCode, exitCode) << run.err;
    EXPECT_EQ(run.out, "");
    ASSERT_FALSE(run.err.empty());
    EXPECT_EQ(run.err.find('\n'), run.err.size() - 1) << "more than one line: " << run.err;
    EXPECT_EQ(run.err.rfind("stvd: ", 0), 0u) << run.err;
    EXPECT_NE(run.err.find(mentioned), std::string::npos) << run.err;
    if (!problem.empty()) {
      EXPECT_NE(run.err.find(problem), std::string::npos) << run.err;
    }
    EXPECT_TRUE(listFolder(path("out")).empty()) << "left a file behind";
  }

  /// A copy of the first `bytes` bytes of a file.
  std::string truncatedCopy(const std::string& from, const std::string& name, std::size_t bytes) {
    std::ifstream in(from, std::ios::binary);
    std::string content(bytes, '\0');
    in.read(content.data(), static_cast<std::streamsize>(bytes));
    std::ofstream(input(name), std::ios::binary).write(content.data(), in.gcount());
    return input(name);
  }

  std::string knownFieldNrrd() {
    KnownField field;
    writeTensorNrrdByHand(input("field.nrrd"), field.geometry, "left-posterior-superior",
                          std::vector<SymTensor3>(field.voxelCount(), field.lpsMetric()), nullptr);
    return input("field.nrrd");
  }

  const std::string brain = sampleFile("dti_tensor_dipy5d.nii.gz");
};

TEST_F(ToolBadInput, MissingInput) {
  expectFailure({input("nothing.nii.gz"), "--seed-voxel", "1,1,1", "-o", output()}, kInput, input("nothing.nii.gz"),
                "no such file");
}

TEST_F(ToolBadInput, FileThatIsNoImage) {
  std::ofstream(input("notes.nii.gz")) << "these are notes, not an image\n";
  expectFailure({input("notes.nii.gz"), "--seed-voxel", "1,1,1", "-o", output()}, kInput, input("notes.nii.gz"));
}

TEST_F(ToolBadInput, EmptyFile) {
  std::ofstream(input("empty.nrrd"));
  expectFailure({input("empty.nrrd"), "--seed-voxel", "1,1,1", "-o", output()}, kInput, input("empty.nrrd"), "empty");
}

TEST_F(ToolBadInput, TruncatedCompressedNifti) {
  const std::string cut = truncatedCopy(brain, "cut.nii.gz", fs::file_size(brain) / 2);
  expectFailure({cut, "--seed-voxel", "55,54,15", "-o", output()}, kInput, cut, "cut short");
}

TEST_F(ToolBadInput, TruncatedRawNrrd) {
  const std::string whole = knownFieldNrrd();
  const std::string cut = truncatedCopy(whole, "cut.nrrd", fs::file_size(whole) - 100);
  expectFailure({cut, "--tensor-kind", "metric", "--seed-voxel", "5,4,3", "-o", output()}, kInput, cut);
}

TEST_F(ToolBadInput, TruncatedCompressedNrrd) {
  const std::string teem = sampleFile("dti_tensor_teem.nrrd");
  const std::string cut = truncatedCopy(teem, "cut.nrrd", fs::file_size(teem) * 3 / 4);
  expectFailure({cut, "--seed-voxel", "55,54,15", "-o", output()}, kInput, cut);
}

TEST_F(ToolBadInput, TruncatedRawNifti) {
  KnownField field;
  writeNiftiByHand(input("whole.nii"), field.geometry, NiftiTensorLayout::SymMatrix5D,
                   std::vector<std::array<float, 6>>(field.voxelCount(), {1, 0, 1, 0, 0, 1}));
  const std::string cut = truncatedCopy(input("whole.nii"), "cut.nii", fs::file_size(input("whole.nii")) - 64);
  expectFailure({cut, "--seed-voxel", "5,4,3", "-o", output()}, kInput, cut, "truncated");
}

TEST_F(ToolBadInput, WrongComponentCount) {
  KnownField field;
  writeScalarNiftiByHand(input("three.nii"), field.geometry, std::vector<float>(3 * field.voxelCount(), 1.f), 3);
  expectFailure({input("three.nii"), "--tensor-order", "fsl", "--seed-voxel", "5,4,3", "-o", output()}, kInput,
                input("three.nii"), "needs 6 volumes");
}

TEST_F(ToolBadInput, ScalarImageGivenAsTensors) {
  expectFailure({sampleFile("dti_FA.nii.gz"), "--seed-voxel", "55,54,15", "-o", output()}, kInput,
                sampleFile("dti_FA.nii.gz"), "scalar image");
}

TEST_F(ToolBadInput, SixVolumesWithoutAnOrder) {
  expectFailure({sampleFile("dti_tensor_fsl6.nii.gz"), "--seed-voxel", "55,54,15", "-o", output()}, kInput,
                sampleFile("dti_tensor_fsl6.nii.gz"), "--tensor-order");
}

TEST_F(ToolBadInput, MaskOfAnotherGeometry) {
  KnownField field;
  writeScalarNiftiByHand(input("small_mask.nii"), field.geometry, std::vector<float>(field.voxelCount(), 1.f));
  expectFailure({brain, "--mask", input("small_mask.nii"), "--seed-voxel", "55,54,15", "-o", output()}, kInput,
                input("small_mask.nii"), "another grid");
}

TEST_F(ToolBadInput, SeedLabelsOfAnotherGeometry) {
  KnownField field;
  writeScalarNiftiByHand(input("labels.nii"), field.geometry, std::vector<float>(field.voxelCount(), 1.f));
  expectFailure({brain, "--seeds", input("labels.nii"), "-o", output()}, kInput, input("labels.nii"), "another grid");
}

TEST_F(ToolBadInput, SeedVoxelOutsideTheImage) {
  expectFailure({brain, "--seed-voxel", "55,54,32", "-o", output()}, kDomain, brain, "outside the image");
  expectFailure({brain, "--seed-voxel", "-1,54,15", "-o", output()}, kDomain, brain, "outside the image");
}

TEST_F(ToolBadInput, SeedPointOutsideTheImage) {
  expectFailure({brain, "--seed-point", "6.4,11.6,176.3", "-o", output()}, kDomain, brain, "outside the image");
}

TEST_F(ToolBadInput, SeedOutsideTheMask) {
  // Voxel (0, 0, 0) lies outside the brain, where the tensors are zero.
  expectFailure({brain, "--seed-voxel", "0,0,0", "-o", output()}, kDomain, brain, "outside the domain");
  const std::string teem = sampleFile("dti_tensor_teem.nrrd");
  expectFailure({teem, "--seed-voxel", "0,0,0", "-o", output()}, kDomain, teem, "outside the mask");
}

TEST_F(ToolBadInput, SeedLabelsAllOutsideTheDomain) {
  const imaging::ScalarImage fa = imaging::readScalarImage(sampleFile("dti_FA.nii.gz"));
  std::vector<float> labels(fa.values.size(), 0.f);
  labels[0] = 1.f;
  imaging::writeScalarImage(input("labels.nii.gz"), fa.geometry, labels);
  expectFailure({brain, "--seeds", input("labels.nii.gz"), "-o", output()}, kDomain, input("labels.nii.gz"),
                "inside the domain");
}

TEST_F(ToolBadInput, EmptyDomain) {
  const imaging::ScalarImage fa = imaging::readScalarImage(sampleFile("dti_FA.nii.gz"));
  imaging::writeScalarImage(input("empty_mask.nii.gz"), fa.geometry, std::vector<float>(fa.values.size(), 0.f));
  expectFailure({brain, "--mask", input("empty_mask.nii.gz"), "--seed-voxel", "55,54,15", "-o", output()}, kDomain,
                brain, "domain is empty");
}

TEST_F(ToolBadInput, OutputInAMissingFolder) {
  const std::string missing = path("out/no/such/folder/d.nii.gz");
  expectFailure({brain, "--seed-voxel", "55,54,15", "-o", missing}, kOutput, missing, "does not exist");
  expectFailure({brain, "--seed-voxel", "55,54,15", "-o", output(), "--stats", path("nowhere/s.json")}, kOutput,
                path("nowhere/s.json"), "does not exist");
}

TEST_F(ToolBadInput, OutputWithAnUnsupportedExtension) {
  expectFailure({brain, "--seed-voxel", "55,54,15", "-o", output("d.png")}, kUsage, output("d.png"), "unsupported");
}

TEST_F(ToolBadInput, LanthierNeedsItsNumberOfSteinerPoints) {
  expectFailure({brain, "--seed-voxel", "55,54,15", "--method", "lanthier", "-o", output()}, kUsage, "lanthier",
                "--steiner");
}

TEST_F(ToolBadInput, BadCommandLines) {
  expectFailure({brain, "--seed-voxel", "55,54", "-o", output()}, kUsage, "--seed-voxel");
  expectFailure({brain, "--seed-voxel", "55,54,15", "-o", output(), "--frobnicate"}, kUsage, "--frobnicate");
  expectFailure({brain, "-o", output()}, kUsage, "no seed");
  expectFailure({brain, "--seed-voxel", "55,54,15"}, kUsage, "-o OUTPUT");
  expectFailure({brain, "--seed-voxel", "55,54,15", "--k", "17", "-o", output()}, kUsage, "--k");
  expectFailure({brain, "--seed-voxel", "55,54,15", "--method", "dijkstra", "--k", "4", "-o", output()}, kUsage,
                "--k");
  expectFailure({brain, "--seed-voxel", "55,54,15", "--stencil", "27", "-o", output()}, kUsage, "--stencil");
  expectFailure({brain, "--seed-voxel", "55,54,15", "--tensor-order", "dipy", "-o", output()}, kUsage,
                "--tensor-order");
  expectFailure({brain, "--seed-voxel", "55,54,15", "--tensor-frame", "scanner", "-o", output()}, kUsage,
                "--tensor-frame");
  expectFailure({brain, "--seed-voxel", "55,54,15", "--max-anisotropy", "0.5", "-o", output()}, kUsage,
                "--max-anisotropy");
}

TEST(ToolCommands, UnknownCommandAndNoCommandAreUsageErrors) {
  EXPECT_EQ(runTool({"frobnicate"}).exitCode, kUsage);
  EXPECT_EQ(runTool({}).exitCode, kUsage);
}

}  // namespace
}  // namespace stvd::testing
