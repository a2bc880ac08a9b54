// Every layout, order and frame the writer supports reads back as the same
// tensors on the same grid.
#include <gtest/gtest.h>

#include <cmath>
#include <tuple>

#include "stvd/errors.hpp"
#include "stvd/itk/tensor_volume_io.hpp"
#include "test_support.hpp"

namespace stvd::imaging {
namespace {

using stvd::testing::HandGeometry;
using stvd::testing::relativeDifference;
using stvd::testing::rotation;

/// An oblique grid with unequal spacings and distinct tensors in every
/// voxel, so that swapped components, axes or frames all show.
TensorVolume distinctVolume() {
  HandGeometry h;
  h.size = {5, 4, 3};
  h.spacing = {1.25, 2.0, 2.5};
  h.originLps = {-31.5, 12.25, 4.0};
  h.directionLps = rotation(1, 2, 3, 25);
  TensorVolume v;
  v.geometry = h.grid();
  for (int k = 0; k < 3; ++k)
    for (int j = 0; j < 4; ++j)
      for (int i = 0; i < 5; ++i) {
        const float s = 1.f + 0.1f * i + 0.01f * j + 0.001f * k;
        v.tensors.push_back({3.f * s, 0.2f * s, -0.3f, 2.f, 0.15f * s, 1.f + 0.05f * i});
      }
  return v;
}

void expectSameGrid(const GridGeometry& a, const GridGeometry& b) {
  EXPECT_EQ(a.size, b.size);
  for (int i = 0; i < 3; ++i) {
    EXPECT_NEAR(a.spacing[i], b.spacing[i], 1e-5);
    EXPECT_NEAR(a.origin[i], b.origin[i], 1e-4);
  }
  for (int i = 0; i < 9; ++i) EXPECT_NEAR(a.direction[i], b.direction[i], 1e-6);
}

using RoundTrip = std::tuple<std::string, TensorFileLayout, TensorOrder, TensorFrame>;

class TensorRoundTrip : public stvd::testing::ScratchFolderTest,
                        public ::testing::WithParamInterface<RoundTrip> {};

TEST_P(TensorRoundTrip, ReadsBackTheSameTensorsOnTheSameGrid) {
  const auto& [extension, layout, order, frame] = GetParam();
  const TensorVolume written = distinctVolume();
  const std::string file = path("tensors" + extension);
  writeTensorVolume(file, written, {layout, order, frame});

  TensorReadOptions options;
  options.frame = frame;
  if (layout == TensorFileLayout::NiftiSixVolumes || layout == TensorFileLayout::MrtrixSixVolumes)
    options.order = order;
  const TensorReadResult read = readTensorVolume(file, options);
  EXPECT_EQ(read.info.layout, layout);
  EXPECT_EQ(read.info.frame, frame);
  expectSameGrid(read.volume.geometry, written.geometry);
  ASSERT_EQ(read.volume.tensors.size(), written.tensors.size());
  double worst = 0.0;
  for (std::size_t v = 0; v < written.tensors.size(); ++v)
    worst = std::max(worst, relativeDifference(read.volume.tensors[v], written.tensors[v]));
  EXPECT_LT(worst, 2e-6);
  EXPECT_TRUE(read.volume.mask.empty());
  // Only the file itself is left in the folder: no staging leftovers.
  EXPECT_EQ(listFolder(folder()), std::vector<std::string>{"tensors" + extension});
}

std::string roundTripName(const ::testing::TestParamInfo<RoundTrip>& info) {
  const auto& [extension, layout, order, frame] = info.param;
  std::string name = extension == ".nrrd"    ? "Nrrd"
                     : extension == ".nii"   ? "Nii"
                     : extension == ".mif"   ? "Mif"
                     : extension == ".mif.gz" ? "MifGz"
                                              : "NiiGz";
  const bool sixVolumes =
      layout == TensorFileLayout::NiftiSixVolumes || layout == TensorFileLayout::MrtrixSixVolumes;
  name += sixVolumes ? "SixVolumes" : layout == TensorFileLayout::NiftiSymMatrix5D ? "SymMatrix5D" : "SymMatrix";
  if (sixVolumes) name += "_" + tensorOrderName(order);
  return name + "_" + tensorFrameName(frame);
}

INSTANTIATE_TEST_SUITE_P(
    EveryLayoutOrderAndFrame, TensorRoundTrip,
    ::testing::Values(
        RoundTrip{".nii.gz", TensorFileLayout::NiftiSymMatrix5D, TensorOrder::Lower, TensorFrame::Voxel},
        RoundTrip{".nii.gz", TensorFileLayout::NiftiSymMatrix5D, TensorOrder::Lower, TensorFrame::World},
        RoundTrip{".nii", TensorFileLayout::NiftiSymMatrix5D, TensorOrder::Lower, TensorFrame::Voxel},
        RoundTrip{".nii.gz", TensorFileLayout::NiftiSixVolumes, TensorOrder::Fsl, TensorFrame::Voxel},
        RoundTrip{".nii.gz", TensorFileLayout::NiftiSixVolumes, TensorOrder::Fsl, TensorFrame::World},
        RoundTrip{".nii.gz", TensorFileLayout::NiftiSixVolumes, TensorOrder::Mrtrix, TensorFrame::Voxel},
        RoundTrip{".nii.gz", TensorFileLayout::NiftiSixVolumes, TensorOrder::Mrtrix, TensorFrame::World},
        RoundTrip{".nii", TensorFileLayout::NiftiSixVolumes, TensorOrder::Lower, TensorFrame::Voxel},
        RoundTrip{".nii", TensorFileLayout::NiftiSixVolumes, TensorOrder::Lower, TensorFrame::World},
        RoundTrip{".nrrd", TensorFileLayout::NrrdSymMatrix, TensorOrder::Fsl, TensorFrame::Voxel},
        RoundTrip{".nrrd", TensorFileLayout::NrrdSymMatrix, TensorOrder::Fsl, TensorFrame::World},
        RoundTrip{".mif", TensorFileLayout::MrtrixSixVolumes, TensorOrder::Mrtrix, TensorFrame::World},
        RoundTrip{".mif", TensorFileLayout::MrtrixSixVolumes, TensorOrder::Fsl, TensorFrame::Voxel},
        RoundTrip{".mif.gz", TensorFileLayout::MrtrixSixVolumes, TensorOrder::Mrtrix, TensorFrame::World}),
    roundTripName);

class TensorFiles : public stvd::testing::ScratchFolderTest {};

TEST_F(TensorFiles, ReadingInTheOtherFrameGivesOtherTensors) {
  // The frame is not a label: components written along the index axes and
  // read as world components are rotated by the grid's obliquity.
  const TensorVolume written = distinctVolume();
  const std::string file = path("voxel_frame.nii.gz");
  writeTensorVolume(file, written, {TensorFileLayout::NiftiSymMatrix5D, TensorOrder::Lower, TensorFrame::Voxel});
  const TensorReadResult asWorld = readTensorVolume(file, {std::nullopt, TensorFrame::World});
  EXPECT_GT(relativeDifference(asWorld.volume.tensors[7], written.tensors[7]), 0.05);
}

TEST_F(TensorFiles, ReadingInTheWrongOrderGivesOtherTensors) {
  const TensorVolume written = distinctVolume();
  const std::string file = path("mrtrix.nii.gz");
  writeTensorVolume(file, written, {TensorFileLayout::NiftiSixVolumes, TensorOrder::Mrtrix, TensorFrame::World});
  const TensorReadResult asFsl = readTensorVolume(file, {TensorOrder::Fsl, TensorFrame::World});
  EXPECT_GT(relativeDifference(asFsl.volume.tensors[7], written.tensors[7]), 0.05);
}

TEST_F(TensorFiles, ASixVolumeNiftiWithoutAnOrderIsAnErrorThatNamesTheOption) {
  const std::string file = path("six.nii.gz");
  writeTensorVolume(file, distinctVolume(), {TensorFileLayout::NiftiSixVolumes, TensorOrder::Fsl, TensorFrame::Voxel});
  try {
    readTensorVolume(file);
    FAIL() << "no error";
  } catch (const ImageIoError& e) {
    EXPECT_NE(std::string(e.what()).find(file), std::string::npos);
    EXPECT_NE(std::string(e.what()).find("--tensor-order"), std::string::npos);
  }
}

TEST_F(TensorFiles, AnOrderThatContradictsAFixedLayoutIsAnError) {
  const std::string nifti = path("sym.nii.gz"), nrrd = path("sym.nrrd");
  writeTensorVolume(nifti, distinctVolume(), {TensorFileLayout::NiftiSymMatrix5D, TensorOrder::Lower, TensorFrame::Voxel});
  writeTensorVolume(nrrd, distinctVolume(), {TensorFileLayout::NrrdSymMatrix, TensorOrder::Fsl, TensorFrame::Voxel});
  EXPECT_THROW(readTensorVolume(nifti, {TensorOrder::Fsl, std::nullopt}), ImageIoError);
  EXPECT_NO_THROW(readTensorVolume(nifti, {TensorOrder::Lower, std::nullopt}));
  EXPECT_THROW(readTensorVolume(nrrd, {TensorOrder::Mrtrix, std::nullopt}), ImageIoError);
  EXPECT_NO_THROW(readTensorVolume(nrrd, {TensorOrder::Fsl, std::nullopt}));
}

}  // namespace
}  // namespace stvd::imaging
