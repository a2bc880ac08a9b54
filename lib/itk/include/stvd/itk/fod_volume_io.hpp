// Fibre orientation distribution (FOD) images read as files: spherical-
// harmonic coefficients along the fourth axis of a 4-D NIfTI file (through
// ITK) or an MRtrix image (our own reader, readMrtrixFodVolume in
// stvd/imaging/fod_field.hpp, which needs no ITK), with their basis and
// frame stated or taken from the format. docs/fod.md.
#pragma once

#include <optional>
#include <string>

#include "stvd/imaging/fod_field.hpp"

namespace stvd::imaging {

/// Reads an FOD image from a .nii, .nii.gz (X Y Z N, N = 1, 6, 15, 28, 45,
/// 66 or 91 coefficients: lmax 0 to 12), .mif, .mif.gz or .mih file (X Y Z
/// N). The header is screened before the data are read, as for every image
/// (docs/reliability.md). Throws ImageIoError with one line naming the file:
/// unreadable, truncated or hostile file, not 4-D, a count of volumes that
/// is no lmax's, a NaN or infinite coefficient (with its voxel), a NIfTI
/// file without a basis, an unknown basis name.
FodField readFodVolume(const std::string& path, const FodReadOptions& options = {});

}  // namespace stvd::imaging
