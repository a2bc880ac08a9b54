// The tensor frame check (tensor_frame_check.hpp) on the shipped brain
// under every flip and permutation of its components along the voxel axes,
// on volumes too small or too noisy to say anything (never a false alarm),
// and in the tool: stvd info reports it, a run of a reoriented image stops
// with exit 3 naming the transform that fits, --accept-misaligned-tensors
// goes on.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <filesystem>
#include <random>
#include <set>
#include <string>
#include <vector>

#include "stvd/imaging/tensor_frame_check.hpp"
#include "stvd/imaging/tensor_frames.hpp"
#include "stvd/itk/scalar_image_io.hpp"
#include "stvd/itk/tensor_volume_io.hpp"
#include "test_support.hpp"

namespace stvd::testing {
namespace {

using imaging::AxisTransform;
using imaging::TensorFrameVerdict;

/// Every one of the 48 signed permutations of i, j, k.
std::vector<AxisTransform> allSignedPermutations() {
  std::vector<AxisTransform> all;
  std::array<int, 3> axis{0, 1, 2};
  do {
    for (int bits = 0; bits < 8; ++bits) {
      AxisTransform t;
      t.axis = axis;
      for (int a = 0; a < 3; ++a) t.sign[a] = (bits >> a) & 1 ? -1 : 1;
      all.push_back(t);
    }
  } while (std::next_permutation(axis.begin(), axis.end()));
  return all;
}

/// The inverse of a signed permutation (its transpose).
AxisTransform inverse(const AxisTransform& t) {
  AxisTransform inv;
  for (int a = 0; a < 3; ++a) {
    inv.axis[t.axis[a]] = a;
    inv.sign[t.axis[a]] = t.sign[a];
  }
  return inv;
}

/// Tensors whose components were given in the wrong frame: W D W^T along
/// the voxel axes, back in LPS as stvd holds them.
std::vector<SymTensor3> misaligned(const std::vector<SymTensor3>& lps, const GridGeometry& g, const AxisTransform& w) {
  const imaging::Matrix3 r = imaging::voxelAxes(g);
  const imaging::Matrix3 rt{r[0], r[3], r[6], r[1], r[4], r[7], r[2], r[5], r[8]};
  std::vector<SymTensor3> out(lps.size());
  for (std::size_t v = 0; v < lps.size(); ++v)
    out[v] = imaging::changeTensorFrame(imaging::transformTensor(imaging::changeTensorFrame(lps[v], rt), w), r);
  return out;
}

class SampleBrainFrames : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    read_ = new imaging::TensorReadResult(imaging::readTensorVolume(sampleFile("dti_tensor_dipy5d.nii.gz")));
    const imaging::ScalarImage mask = imaging::readScalarImage(sampleFile("dti_mask.nii.gz"));
    domain_ = new std::vector<std::uint8_t>(mask.values.size());
    for (std::size_t v = 0; v < mask.values.size(); ++v) (*domain_)[v] = mask.values[v] != 0.f;
  }
  static void TearDownTestSuite() {
    delete read_;
    delete domain_;
  }
  static imaging::TensorReadResult* read_;
  static std::vector<std::uint8_t>* domain_;
};
imaging::TensorReadResult* SampleBrainFrames::read_ = nullptr;
std::vector<std::uint8_t>* SampleBrainFrames::domain_ = nullptr;

TEST(AxisTransforms, TwentyFourDistinguishableFramesNamedByTheirCorrection) {
  const std::vector<AxisTransform> frames = imaging::distinguishableAxisTransforms();
  ASSERT_EQ(frames.size(), 24u);
  EXPECT_TRUE(frames.front().isIdentity());
  std::set<std::string> names;
  for (const AxisTransform& t : frames) names.insert(imaging::axisTransformText(t));
  EXPECT_EQ(names.size(), 24u);
  // T and -T give the same tensors; the name is the one with fewer flips.
  AxisTransform flipJK;
  flipJK.sign = {1, -1, -1};
  EXPECT_EQ(imaging::axisTransformText(imaging::canonicalAxisTransform(flipJK)), "(-i, j, k)");
  EXPECT_EQ(imaging::axisTransformWords(flipJK), "flipped along i");
  AxisTransform swap;
  swap.axis = {1, 0, 2};
  EXPECT_EQ(imaging::axisTransformWords(swap), "with i and j swapped");
  const SymTensor3 d{1.f, 0.1f, 0.2f, 2.f, 0.3f, 3.f};
  const SymTensor3 a = imaging::transformTensor(d, flipJK), b = imaging::transformTensor(d, {{0, 1, 2}, {-1, 1, 1}});
  EXPECT_EQ(a.xy, b.xy);
  EXPECT_EQ(a.xz, b.xz);
  EXPECT_EQ(a.yz, b.yz);
  EXPECT_EQ(a.xy, -0.1f);
}

// The shipped brain as read: the frame as read wins, by a clear margin.
TEST_F(SampleBrainFrames, TheFrameAsReadFitsBest) {
  const imaging::TensorFrameCheck c = imaging::checkTensorFrame(read_->volume.tensors, read_->volume.geometry, *domain_);
  EXPECT_EQ(c.verdict, TensorFrameVerdict::Consistent) << imaging::tensorFrameCheckSummary(c);
  EXPECT_EQ(c.seeds, 2000u);
  EXPECT_GT(c.margin, 1.3) << imaging::tensorFrameCheckSummary(c);
  EXPECT_GT(c.readMeanMm, 15.0);
  RecordProperty("summary", imaging::tensorFrameCheckSummary(c));
}

// Every one of the 48 flips and permutations of the components: each is
// detected, and the transform named is the one that undoes it. A transform
// and its negative are the same tensors, so the 48 come in 24 pairs with
// identical measurements (margin 1 between them: they cannot be told apart,
// and need not be).
TEST_F(SampleBrainFrames, EveryFlipAndPermutationIsDetectedAndUndone) {
  const GridGeometry& g = read_->volume.geometry;
  double smallestRatio = INFINITY;
  std::string smallestName;
  for (const AxisTransform& w : allSignedPermutations()) {
    const imaging::TensorFrameCheck c = imaging::checkTensorFrame(misaligned(read_->volume.tensors, g, w), g, *domain_);
    const AxisTransform undo = imaging::canonicalAxisTransform(inverse(w));
    const std::string name = imaging::axisTransformText(w);
    if (undo.isIdentity()) {
      EXPECT_EQ(c.verdict, TensorFrameVerdict::Consistent) << name << ": " << imaging::tensorFrameCheckSummary(c);
      continue;
    }
    EXPECT_EQ(c.verdict, TensorFrameVerdict::Mismatch) << name << ": " << imaging::tensorFrameCheckSummary(c);
    EXPECT_EQ(c.best, undo) << name << ": " << imaging::tensorFrameCheckSummary(c);
    if (c.ratio < smallestRatio) {
      smallestRatio = c.ratio;
      smallestName = name;
    }
  }
  RecordProperty("smallest_ratio", std::to_string(smallestRatio) + " for " + smallestName);
  EXPECT_GT(smallestRatio, 1.5) << smallestName;
}

// Too little to go on: a tiny phantom, a volume of low FA, a noise volume.
// None may come out as a mismatch (which would stop a run).
TEST(TensorFrameCheckWithoutEvidence, SmallLowFaAndNoiseVolumesAreNeverAMismatch) {
  GridGeometry g;
  g.size = {6, 6, 6};
  g.spacing = {2, 2, 2};
  // A tiny phantom: one straight tract along i.
  std::vector<SymTensor3> phantom(g.voxelCount(), SymTensor3{3.f, 0.f, 0.f, 1.f, 0.f, 1.f});
  imaging::TensorFrameCheck c = imaging::checkTensorFrame(phantom, g, {});
  EXPECT_NE(c.verdict, TensorFrameVerdict::Mismatch) << imaging::tensorFrameCheckSummary(c);
  // Nearly isotropic tensors: no seed.
  g.size = {20, 20, 20};
  std::vector<SymTensor3> isotropic(g.voxelCount(), SymTensor3{1.1f, 0.f, 0.f, 1.f, 0.f, 1.f});
  c = imaging::checkTensorFrame(isotropic, g, {});
  EXPECT_EQ(c.verdict, TensorFrameVerdict::Inconclusive);
  EXPECT_NE(c.reason.find("only 0 voxels"), std::string::npos) << c.reason;
  // Noise: anisotropic tensors in random directions, 100 times over.
  std::mt19937 random(31);
  std::normal_distribution<double> normal;
  int mismatches = 0;
  double largestRatio = 0.0;
  for (int trial = 0; trial < 20; ++trial) {
    std::vector<SymTensor3> noise(g.voxelCount());
    for (SymTensor3& t : noise) {
      double e[3] = {normal(random), normal(random), normal(random)};
      const double n = std::sqrt(e[0] * e[0] + e[1] * e[1] + e[2] * e[2]);
      for (double& x : e) x /= n;
      // 0.3 + 1.7 e e^T: FA about 0.8.
      t = {float(0.3 + 1.7 * e[0] * e[0]), float(1.7 * e[0] * e[1]), float(1.7 * e[0] * e[2]),
           float(0.3 + 1.7 * e[1] * e[1]), float(1.7 * e[1] * e[2]), float(0.3 + 1.7 * e[2] * e[2])};
    }
    c = imaging::checkTensorFrame(noise, g, {});
    mismatches += c.verdict == TensorFrameVerdict::Mismatch;
    largestRatio = std::max(largestRatio, c.ratio);
  }
  EXPECT_EQ(mismatches, 0) << "largest ratio " << largestRatio;
  RecordProperty("noise_largest_ratio", std::to_string(largestRatio));
}

class ToolFrameCheck : public ScratchFolderTest {};

// The pitfall itself: the image reordered along i with its header (as
// nib.as_closest_canonical does for this LAS brain) and the components
// left as they were.
TEST_F(ToolFrameCheck, AReorientedImageStopsWithExitThreeNamingTheFlipAndInfoShowsIt) {
  const imaging::TensorReadResult read = imaging::readTensorVolume(sampleFile("dti_tensor_dipy5d.nii.gz"));
  const GridGeometry& g = read.volume.geometry;
  // Voxel i becomes nx-1-i; the geometry follows (the first axis reversed);
  // the components stay as they were along the old axes.
  GridGeometry flipped = g;
  for (int r = 0; r < 3; ++r) {
    flipped.origin[r] = g.origin[r] + g.direction[3 * r] * g.spacing[0] * double(g.size[0] - 1);
    flipped.direction[3 * r] = -g.direction[3 * r];
  }
  const imaging::Matrix3 r = imaging::voxelAxes(g);
  const imaging::Matrix3 rt{r[0], r[3], r[6], r[1], r[4], r[7], r[2], r[5], r[8]};
  imaging::TensorVolume volume;
  volume.geometry = flipped;
  volume.tensors.resize(read.volume.tensors.size());
  const imaging::Matrix3 rf = imaging::voxelAxes(flipped);
  for (std::size_t k = 0; k < g.size[2]; ++k)
    for (std::size_t j = 0; j < g.size[1]; ++j)
      for (std::size_t i = 0; i < g.size[0]; ++i) {
        const std::size_t from = i + g.size[0] * (j + g.size[1] * k);
        const std::size_t to = (g.size[0] - 1 - i) + g.size[0] * (j + g.size[1] * k);
        // The old voxel-frame components, taken as the new voxel frame's.
        volume.tensors[to] = imaging::changeTensorFrame(imaging::changeTensorFrame(read.volume.tensors[from], rt), rf);
      }
  imaging::TensorWriteOptions write;
  write.layout = imaging::TensorFileLayout::NiftiSymMatrix5D;
  imaging::writeTensorVolume(path("canonical.nii.gz"), volume, write);

  const ToolRun stopped = runTool({"distance", path("canonical.nii.gz"), "--seed-voxel", "56,54,15", "-o",
                                   path("d.nii.gz"), "-q"});
  EXPECT_EQ(stopped.exitCode, 3) << stopped.err;
  EXPECT_EQ(stopped.err.find('\n'), stopped.err.size() - 1) << "not one line: " << stopped.err;
  EXPECT_NE(stopped.err.find("flipped along i (-i, j, k)"), std::string::npos) << stopped.err;
  EXPECT_NE(stopped.err.find("--accept-misaligned-tensors"), std::string::npos) << stopped.err;
  EXPECT_FALSE(std::filesystem::exists(path("d.nii.gz")));

  const ToolRun accepted = runTool({"distance", path("canonical.nii.gz"), "--seed-voxel", "56,54,15", "-o",
                                    path("d.nii.gz"), "-q", "--accept-misaligned-tensors"});
  EXPECT_EQ(accepted.exitCode, 0) << accepted.err;

  const ToolRun info = runTool({"info", path("canonical.nii.gz")});
  ASSERT_EQ(info.exitCode, 0) << info.err;
  EXPECT_NE(info.out.find("Frame check: mismatch: the components fit the image flipped along i, (-i, j, k)"),
            std::string::npos)
      << info.out;
  const ToolRun original = runTool({"info", sampleFile("dti_tensor_dipy5d.nii.gz")});
  ASSERT_EQ(original.exitCode, 0) << original.err;
  EXPECT_NE(original.out.find("Frame check: consistent: the frame as read fits best"), std::string::npos)
      << original.out;
  EXPECT_NE(original.out.find("(i, j, k)"), std::string::npos);
}

}  // namespace
}  // namespace stvd::testing
