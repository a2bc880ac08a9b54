// Component orders and frame names: the conventions every reader and
// writer relies on.
#include <gtest/gtest.h>

#include "stvd/imaging/tensor_layout.hpp"

namespace stvd::imaging {
namespace {

// A tensor whose six components are all different, so that any mix-up of
// two components shows.
const SymTensor3 kDistinct{11.f, 12.f, 13.f, 22.f, 23.f, 33.f};

TEST(TensorOrder, LowerIsTheNiftiStandardLowerTriangleRowByRow) {
  float c[6];
  componentsOfTensor(kDistinct, TensorOrder::Lower, c);
  EXPECT_EQ(std::vector<float>(c, c + 6), (std::vector<float>{11, 12, 22, 13, 23, 33}));
}

TEST(TensorOrder, FslIsTheUpperTriangleRowByRow) {
  float c[6];
  componentsOfTensor(kDistinct, TensorOrder::Fsl, c);
  EXPECT_EQ(std::vector<float>(c, c + 6), (std::vector<float>{11, 12, 13, 22, 23, 33}));
}

TEST(TensorOrder, MrtrixPutsTheDiagonalFirst) {
  float c[6];
  componentsOfTensor(kDistinct, TensorOrder::Mrtrix, c);
  EXPECT_EQ(std::vector<float>(c, c + 6), (std::vector<float>{11, 22, 33, 12, 13, 23}));
}

TEST(TensorOrder, ReadingUndoesWritingInEveryOrder) {
  for (TensorOrder order : {TensorOrder::Lower, TensorOrder::Fsl, TensorOrder::Mrtrix}) {
    float c[6];
    componentsOfTensor(kDistinct, order, c);
    const SymTensor3 back = tensorFromComponents(c, order);
    EXPECT_EQ(back.xx, kDistinct.xx);
    EXPECT_EQ(back.xy, kDistinct.xy);
    EXPECT_EQ(back.xz, kDistinct.xz);
    EXPECT_EQ(back.yy, kDistinct.yy);
    EXPECT_EQ(back.yz, kDistinct.yz);
    EXPECT_EQ(back.zz, kDistinct.zz);
  }
}

TEST(TensorOrder, NamesAndAliasesParse) {
  EXPECT_EQ(parseTensorOrder("lower"), TensorOrder::Lower);
  EXPECT_EQ(parseTensorOrder("nifti"), TensorOrder::Lower);
  EXPECT_EQ(parseTensorOrder("fsl"), TensorOrder::Fsl);
  EXPECT_EQ(parseTensorOrder("upper"), TensorOrder::Fsl);
  EXPECT_EQ(parseTensorOrder("mrtrix"), TensorOrder::Mrtrix);
  EXPECT_FALSE(parseTensorOrder("dipy").has_value());
  EXPECT_FALSE(parseTensorOrder("").has_value());
  EXPECT_EQ(tensorOrderComponents(TensorOrder::Lower), "xx,xy,yy,xz,yz,zz");
}

TEST(TensorFrame, DefaultsFollowTheToolsThatWriteEachLayout) {
  EXPECT_EQ(defaultTensorFrame(TensorFileLayout::NiftiSymMatrix5D, TensorOrder::Lower), TensorFrame::Voxel);
  EXPECT_EQ(defaultTensorFrame(TensorFileLayout::NiftiSixVolumes, TensorOrder::Fsl), TensorFrame::Voxel);
  EXPECT_EQ(defaultTensorFrame(TensorFileLayout::NiftiSixVolumes, TensorOrder::Lower), TensorFrame::Voxel);
  EXPECT_EQ(defaultTensorFrame(TensorFileLayout::NiftiSixVolumes, TensorOrder::Mrtrix), TensorFrame::World);
  EXPECT_EQ(defaultTensorFrame(TensorFileLayout::NrrdSymMatrix, TensorOrder::Fsl), TensorFrame::World);
  EXPECT_EQ(defaultTensorFrame(TensorFileLayout::NrrdMaskedSymMatrix, TensorOrder::Fsl), TensorFrame::World);
  EXPECT_EQ(parseTensorFrame("voxel"), TensorFrame::Voxel);
  EXPECT_EQ(parseTensorFrame("world"), TensorFrame::World);
  EXPECT_FALSE(parseTensorFrame("scanner").has_value());
}

}  // namespace
}  // namespace stvd::imaging
