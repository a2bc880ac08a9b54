// Tensor volumes from arrays in memory (NumPy arrays, NiBabel images): the
// grid of a NIfTI-style affine, and the six components of every voxel
// brought into the LPS frame. The file readers go through the same
// conversion, so that an array holding a file's numbers, with the file's
// affine, gives exactly the tensors the file gives.
#pragma once

#include <array>
#include <cstddef>
#include <optional>
#include <string>
#include <vector>

#include "stvd/imaging/tensor_frames.hpp"
#include "stvd/imaging/tensor_layout.hpp"
#include "stvd/imaging/tensor_volume.hpp"
#include "stvd/types.hpp"
#include "stvd/voxel_grid/grid_geometry.hpp"

namespace stvd::imaging {

/// The grid of an image whose 4x4 affine (row-major) takes a voxel index to
/// RAS millimetres, as NIfTI's sform and NiBabel's `affine` do: origin and
/// direction cosines from the affine, in LPS (the inverse of voxelToRas).
/// The spacing is `spacing` when given (NIfTI's pixdim, which ITK reads as
/// the spacing), otherwise the lengths of the affine's columns rounded to
/// single precision as pixdim stores them; either way the grid is exactly
/// the one ITK reads from a NIfTI file with that affine. Throws
/// std::invalid_argument for a non-finite affine, a bottom row other than
/// (0, 0, 0, 1), or a grid GridGeometry::validate() refuses (a zero size, a
/// zero column, columns that are not orthogonal).
GridGeometry gridGeometryFromRasAffine(const std::array<double, 16>& affine, const std::array<std::size_t, 3>& size,
                                       const std::optional<std::array<double, 3>>& spacing = std::nullopt);

/// Where the six numbers of each voxel sit in a buffer, counted in
/// elements: voxel (i, j, k) starts at i * voxelStride[0] + j *
/// voxelStride[1] + k * voxelStride[2], and its components, in `order`, at
/// componentOffset[0..5] from there. Strides may be negative.
struct TensorComponentLayout {
  std::array<std::ptrdiff_t, 3> voxelStride{};
  std::array<std::ptrdiff_t, 6> componentOffset{};
  TensorOrder order = TensorOrder::Fsl;
};

/// The layouts of the file readers: the six components of a voxel one after
/// the other (a NRRD, a NIfTI SYMMATRIX or interleaved file), or one whole
/// volume per component (a NIfTI or MRtrix file of six volumes); voxels in
/// the order i + nx*(j + ny*k).
TensorComponentLayout componentsPerVoxel(const std::array<std::size_t, 3>& size, TensorOrder order);
TensorComponentLayout oneVolumePerComponent(const std::array<std::size_t, 3>& size, TensorOrder order);

/// One tensor per voxel (linear index i + nx*(j + ny*k)): the components
/// read as single precision, put in order and changed into another frame
/// with `frameChange`, M T M^T (componentFrameToLps gives the matrix into
/// LPS; the identity keeps the frame exactly). A voxel with a NaN or
/// infinite component gets a tensor of NaN in every component (no tensor
/// there; outside the domain), whatever its source. Instantiated for float
/// and double.
template <class T>
std::vector<SymTensor3> tensorsFromArray(const T* components, const std::array<std::size_t, 3>& size,
                                         const TensorComponentLayout& layout, const Matrix3& frameChange);

/// The component order of a tensor layout: the fixed order of the 5D NIfTI
/// and NRRD layouts (a stated order must agree), the stated one for NIfTI
/// six volumes (which need one), the stated one or mrtrix for MRtrix six
/// volumes. Throws ImageIoError naming `name` otherwise.
TensorOrder resolveTensorOrder(const std::string& name, TensorFileLayout layout,
                               const std::optional<TensorOrder>& stated);

/// The matrix that takes the components of a file (or array) read as `info`
/// says into LPS: the grid's voxel axes for the voxel frame, RAS to LPS for
/// the world frame of NIfTI, the measurement frame for the world frame of
/// NRRD.
Matrix3 componentFrameToLps(const TensorFileInfo& info, const GridGeometry& geometry);

}  // namespace stvd::imaging
