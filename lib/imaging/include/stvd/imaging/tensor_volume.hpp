// Tensor volumes in memory (an ITK-free struct the core can use directly),
// with what a file said about them and how to read and write them. The
// files themselves: stvd/itk/tensor_volume_io.hpp (NIfTI and NRRD through
// ITK, MRtrix through mrtrix_image.hpp).
//
// Frames. Every TensorVolume in memory holds its tensors in the physical
// LPS frame of its geometry: the frame ITK uses for image geometry, and the
// one the core propagates in (edge vectors are LPS millimetres). On disk a
// tensor's six numbers are given in one of two frames:
//   voxel: along the image's index axes (i, j, k), as DIPY and FSL fits of
//          FSL-style b-vectors usually are;
//   world: along the file's own world axes: RAS scanner space for NIfTI and
//          MRtrix images (as MRtrix writes tensors), the measurement frame mapped into the NRRD
//          space for NRRD.
// A voxel-frame tensor T becomes R T R^T in LPS, with R the direction
// cosines of the index axes (GridGeometry::direction). A NIfTI world-frame
// tensor becomes F T F with F = diag(-1, -1, 1). A NRRD world-frame tensor
// becomes S M T M^T S, with M the measurement frame (its columns are the
// frame's axes in NRRD space coordinates) and S the flip from the NRRD space
// to LPS (identity for left-posterior-superior).
#pragma once

#include <array>
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "stvd/imaging/tensor_frames.hpp"
#include "stvd/imaging/tensor_layout.hpp"
#include "stvd/types.hpp"
#include "stvd/voxel_grid/grid_geometry.hpp"

namespace stvd::imaging {

struct TensorReadOptions {
  /// Required for NiftiSixVolumes; for the other layouts the file fixes the
  /// order and a stated order must agree with it.
  std::optional<TensorOrder> order;
  /// When empty, defaultTensorFrame().
  std::optional<TensorFrame> frame;
};

/// Tensor values read from or written to a file.
struct TensorVolume {
  /// Physical geometry in LPS millimetres, as ITK reports it.
  GridGeometry geometry;
  /// One tensor per voxel (linear index i + nx*(j + ny*k)), components in
  /// the physical LPS frame of `geometry` (see the top of this header).
  std::vector<SymTensor3> tensors;
  /// Empty, or one byte per voxel (0 = masked out): the confidence channel
  /// of a 3D-masked-symmetric-matrix NRRD, thresholded at 0.5 as teem does.
  std::vector<std::uint8_t> mask;
};

/// What a reader found in the file and how it interpreted it.
struct TensorFileInfo {
  TensorFileLayout layout = TensorFileLayout::NiftiSymMatrix5D;
  TensorOrder order = TensorOrder::Lower;
  TensorFrame frame = TensorFrame::Voxel;
  bool frameWasStated = false;  ///< false: the per-format default was used
  /// NRRD only: whether the file has a measurement frame, and that frame
  /// (columns = frame axes) in LPS coordinates.
  bool hasMeasurementFrame = false;
  Matrix3 measurementFrameLps{1, 0, 0, 0, 1, 0, 0, 0, 1};
  /// NRRD only: the file's "space" field ("" when absent).
  std::string nrrdSpace;
  /// The matrix M that took the file's components to LPS (T_LPS = M T M^T):
  /// the voxel axes, the NIfTI RAS flip or the NRRD measurement frame.
  Matrix3 componentsToLps{1, 0, 0, 0, 1, 0, 0, 0, 1};
  /// File's component type, e.g. "float".
  std::string componentType;
  /// What the user should know about a file that was read all the same
  /// (e.g. "has an Analyze 7.5 header ..."), one sentence each.
  std::vector<std::string> warnings;
};

struct TensorReadResult {
  TensorVolume volume;
  TensorFileInfo info;
};

struct TensorWriteOptions {
  /// NIfTI: NiftiSymMatrix5D or NiftiSixVolumes; NRRD: NrrdSymMatrix;
  /// .mif, .mif.gz: MrtrixSixVolumes.
  TensorFileLayout layout = TensorFileLayout::NiftiSymMatrix5D;
  /// The order of a NiftiSixVolumes or MrtrixSixVolumes file (the others
  /// fix their order).
  TensorOrder order = TensorOrder::Fsl;
  /// Voxel: components along the index axes (NRRD: with the index axes as
  /// measurement frame); world: RAS for NIfTI, LPS for NRRD (identity
  /// measurement frame).
  TensorFrame frame = TensorFrame::Voxel;
};

}  // namespace stvd::imaging
