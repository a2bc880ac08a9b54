// NRRD header fields ITK does not hand over as such (through NrrdIO, the
// NRRD library bundled with ITK): the space, the raw measurement frame and
// the confidence channel of a masked tensor file.
#pragma once

#include <string>
#include <vector>

#include "stvd/imaging/tensor_frames.hpp"

namespace stvd::imaging::detail {

struct NrrdTensorHeader {
  /// The "space" field, e.g. "left-posterior-superior"; "" when absent.
  std::string space;
  /// Maps NRRD-space coordinates to LPS: the identity for LPS (and spaces
  /// ITK does not convert), diag(-1,-1,1) for RAS, diag(1,-1,1) for LAS.
  Matrix3 spaceToLps{1, 0, 0, 0, 1, 0, 0, 0, 1};
  bool hasMeasurementFrame = false;
  /// Columns are the measurement frame's axes in NRRD-space coordinates.
  Matrix3 measurementFrame{1, 0, 0, 0, 1, 0, 0, 0, 1};
  /// True for kind 3D-masked-symmetric-matrix.
  bool masked = false;
};

/// Reads the header only. Throws ImageIoError naming the file.
NrrdTensorHeader readNrrdTensorHeader(const std::string& path);

/// Whether the NRRD file's "space" field is left-anterior-superior (its
/// header only; ITK's dictionary names such a space after its own
/// conversion). Throws ImageIoError naming the file.
bool nrrdSpaceIsLeftAnteriorSuperior(const std::string& path);

/// The confidence value of every voxel of a 3D-masked-symmetric-matrix
/// file (the first of its seven components), in ITK's voxel order. Throws
/// ImageIoError naming the file.
std::vector<float> readNrrdConfidence(const std::string& path);

}  // namespace stvd::imaging::detail
