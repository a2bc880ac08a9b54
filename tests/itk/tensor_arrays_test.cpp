// Tensor volumes from arrays in memory: the grid of a NIfTI-style affine and
// the conversion of strided components, which the file readers share.
#include <gtest/gtest.h>

#include <cmath>
#include <string>
#include <vector>

#include "stvd/errors.hpp"
#include "stvd/imaging/streamline_io.hpp"
#include "stvd/imaging/tensor_arrays.hpp"

namespace stvd::imaging {
namespace {

/// An oblique grid with spacings that single precision holds exactly.
GridGeometry obliqueGrid() {
  GridGeometry g;
  g.size = {5, 4, 3};
  g.spacing = {1.0, 1.5, 2.0};
  g.origin = {-31.5, 12.25, 107.0};
  const double c = std::cos(0.3), s = std::sin(0.3);
  g.direction = {c, -s, 0, s, c, 0, 0, 0, -1};  // a rotation and a flip of k
  return g;
}

TEST(GridGeometryFromAffine, UndoesTheVoxelToRasMatrix) {
  const GridGeometry g = obliqueGrid();
  const GridGeometry back = gridGeometryFromRasAffine(voxelToRas(g), g.size);
  EXPECT_EQ(back.size, g.size);
  EXPECT_EQ(back.spacing, g.spacing);
  EXPECT_EQ(back.origin, g.origin);
  for (int e = 0; e < 9; ++e) EXPECT_NEAR(back.direction[e], g.direction[e], 1e-15) << e;
}

TEST(GridGeometryFromAffine, SpacingIsPixdimsSinglePrecisionOrTheOneGiven) {
  GridGeometry g = obliqueGrid();
  g.spacing = {1.1, 1.5, 2.0};  // 1.1 is not a float
  EXPECT_EQ(gridGeometryFromRasAffine(voxelToRas(g), g.size).spacing[0], static_cast<double>(1.1f));
  const std::array<double, 3> pixdim{1.0999999, 1.5, 2.0};
  EXPECT_EQ(gridGeometryFromRasAffine(voxelToRas(g), g.size, pixdim).spacing, pixdim);
}

TEST(GridGeometryFromAffine, RefusesAffinesThatAreNoGrid) {
  const GridGeometry g = obliqueGrid();
  std::array<double, 16> a = voxelToRas(g);
  a[3] = std::nan("");
  EXPECT_THROW(gridGeometryFromRasAffine(a, g.size), std::invalid_argument);
  a = voxelToRas(g);
  a[14] = 1.0;
  EXPECT_THROW(gridGeometryFromRasAffine(a, g.size), std::invalid_argument);
  a = voxelToRas(g);
  a[1] = a[5] = a[9] = 0.0;
  EXPECT_THROW(gridGeometryFromRasAffine(a, g.size), std::invalid_argument);
  a = voxelToRas(g);
  a[1] += 0.5;  // shear
  EXPECT_THROW(gridGeometryFromRasAffine(a, g.size), std::invalid_argument);
}

TEST(TensorsFromArray, AnyStridesGiveTheSameTensors) {
  const std::array<std::size_t, 3> size{3, 2, 2};
  const std::size_t n = 12;
  const Matrix3 identity{1, 0, 0, 0, 1, 0, 0, 0, 1};
  // Voxel v holds the components 10 v + (1..6) in the 'lower' order.
  std::vector<float> interleaved(6 * n), volumes(6 * n), cOrder(6 * n);
  for (std::size_t k = 0, v = 0; k < 2; ++k)
    for (std::size_t j = 0; j < 2; ++j)
      for (std::size_t i = 0; i < 3; ++i, ++v)
        for (int q = 0; q < 6; ++q) {
          const float value = 10.f * v + q + 1;
          interleaved[6 * v + q] = value;
          volumes[v + n * q] = value;
          cOrder[((i * 2 + j) * 2 + k) * 6 + q] = value;  // NumPy's (X, Y, Z, 6) in C order
        }
  TensorComponentLayout layout;
  layout.order = TensorOrder::Lower;
  layout.voxelStride = {6, 18, 36};
  layout.componentOffset = {0, 1, 2, 3, 4, 5};
  const std::vector<SymTensor3> expected = tensorsFromArray(interleaved.data(), size, layout, identity);
  EXPECT_EQ(expected[5].xx, 51.f);
  EXPECT_EQ(expected[5].xy, 52.f);
  EXPECT_EQ(expected[5].yy, 53.f);  // 'lower': xx, xy, yy, xz, yz, zz
  EXPECT_EQ(expected[5].xz, 54.f);

  auto same = [&](const std::vector<SymTensor3>& got) {
    ASSERT_EQ(got.size(), n);
    for (std::size_t v = 0; v < n; ++v) {
      EXPECT_EQ(got[v].xx, expected[v].xx);
      EXPECT_EQ(got[v].xy, expected[v].xy);
      EXPECT_EQ(got[v].xz, expected[v].xz);
      EXPECT_EQ(got[v].yy, expected[v].yy);
      EXPECT_EQ(got[v].yz, expected[v].yz);
      EXPECT_EQ(got[v].zz, expected[v].zz);
    }
  };
  layout.voxelStride = {1, 3, 6};
  for (int q = 0; q < 6; ++q) layout.componentOffset[q] = q * static_cast<std::ptrdiff_t>(n);
  same(tensorsFromArray(volumes.data(), size, layout, identity));
  layout.voxelStride = {24, 12, 6};
  for (int q = 0; q < 6; ++q) layout.componentOffset[q] = q;
  same(tensorsFromArray(cOrder.data(), size, layout, identity));
  // Reversed along i: start at the last i, step back.
  layout.voxelStride = {-24, 12, 6};
  const std::vector<SymTensor3> flipped = tensorsFromArray(cOrder.data() + 48, size, layout, identity);
  EXPECT_EQ(flipped[0].xx, expected[2].xx);
  // Double precision reads the same values.
  const std::vector<double> asDouble(interleaved.begin(), interleaved.end());
  layout.voxelStride = {6, 18, 36};
  same(tensorsFromArray(asDouble.data(), size, layout, identity));
}

TEST(TensorOrderOfALayout, FixedOrdersMustAgreeAndSixVolumesNeedOne) {
  EXPECT_EQ(resolveTensorOrder("t.nii", TensorFileLayout::NiftiSymMatrix5D, std::nullopt), TensorOrder::Lower);
  EXPECT_EQ(resolveTensorOrder("t.nrrd", TensorFileLayout::NrrdSymMatrix, TensorOrder::Fsl), TensorOrder::Fsl);
  EXPECT_EQ(resolveTensorOrder("t.nii", TensorFileLayout::NiftiSixVolumes, TensorOrder::Mrtrix), TensorOrder::Mrtrix);
  EXPECT_THROW(resolveTensorOrder("t.nii", TensorFileLayout::NiftiSymMatrix5D, TensorOrder::Fsl), ImageIoError);
  try {
    resolveTensorOrder("t.nii", TensorFileLayout::NiftiSixVolumes, std::nullopt);
    ADD_FAILURE() << "six volumes without an order were accepted";
  } catch (const ImageIoError& e) {
    EXPECT_EQ(std::string(e.what()), "t.nii: a NIfTI file with six values per voxel and no SYMMATRIX intent does not "
                                     "say its component order; state it with --tensor-order fsl|mrtrix|lower");
  }
}

}  // namespace
}  // namespace stvd::imaging
