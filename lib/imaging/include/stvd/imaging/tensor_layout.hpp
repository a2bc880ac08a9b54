// How a tensor's six numbers are laid out and ordered in a file, and the
// frame they are given in.
#pragma once

#include <optional>
#include <string>

#include "stvd/types.hpp"

namespace stvd::imaging {

/// The order of a tensor's six numbers in a file.
enum class TensorOrder {
  /// xx, xy, yy, xz, yz, zz: lower triangle row by row. The NIfTI-1 standard
  /// for intent SYMMATRIX (5D files), DIPY and ANTs.
  Lower,
  /// xx, xy, xz, yy, yz, zz: upper triangle row by row. FSL dtifit (4D
  /// files) and NRRD 3D-symmetric-matrix.
  Fsl,
  /// xx, yy, zz, xy, xz, yz: diagonal first. MRtrix (4D files).
  Mrtrix,
};

enum class TensorFrame { Voxel, World };

/// How the six numbers are laid out in the file.
enum class TensorFileLayout {
  NiftiSymMatrix5D,    ///< X Y Z 1 6, intent SYMMATRIX (order fixed: lower)
  NiftiSixVolumes,     ///< X Y Z 6 (or X Y Z 1 6 without the intent): order must be stated
  NrrdSymMatrix,       ///< kind 3D-symmetric-matrix (order fixed: fsl)
  NrrdMaskedSymMatrix, ///< kind 3D-masked-symmetric-matrix: confidence + 6 (order fixed: fsl)
  /// MRtrix image (.mif, .mif.gz, .mih), X Y Z 6 (or X Y Z 1 6, as
  /// mrconvert makes it from a NIfTI 5D file): order mrtrix unless stated
  /// (MRtrix's tensor convention; the file does not say it); its voxel frame
  /// is the axes as stored (the layout)
  MrtrixSixVolumes,
};

/// "lower" (alias "nifti"), "fsl" (alias "upper") or "mrtrix"; nullopt otherwise.
std::optional<TensorOrder> parseTensorOrder(const std::string& name);
/// The canonical name: "lower", "fsl", "mrtrix".
std::string tensorOrderName(TensorOrder order);
/// The component list, e.g. "xx,xy,yy,xz,yz,zz".
std::string tensorOrderComponents(TensorOrder order);
/// "voxel" or "world"; nullopt otherwise.
std::optional<TensorFrame> parseTensorFrame(const std::string& name);
std::string tensorFrameName(TensorFrame frame);
/// A short description such as "NIfTI 5D SYMMATRIX".
std::string tensorFileLayoutName(TensorFileLayout layout);

/// The frame a file's tensors are taken to be in when none is stated:
/// voxel for NIfTI in the lower and fsl orders (DIPY, FSL), world for NIfTI
/// in the mrtrix order (MRtrix writes scanner-space tensors), the same for
/// MRtrix images (world in the mrtrix order, voxel otherwise), world for NRRD
/// (the measurement frame says where the components live; a file without
/// one has its components in the NRRD space).
TensorFrame defaultTensorFrame(TensorFileLayout layout, TensorOrder order);

/// The tensor whose six components are `c` in the given order.
SymTensor3 tensorFromComponents(const float c[6], TensorOrder order);
/// The six components of `t` in the given order.
void componentsOfTensor(const SymTensor3& t, TensorOrder order, float c[6]);

}  // namespace stvd::imaging
