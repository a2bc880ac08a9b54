// A side input's grid, from its header alone. A mask, seed or target label
// image, label image or reference image must lie on the grid of the tensors
// (or only its grid is used); a small .nii.gz can declare an enormous grid
// (800^3 voxels of zeros compress to half a megabyte), so its header is
// compared with the tensors' grid before any of its data are read or
// decompressed.
#pragma once

#include <string>
#include <vector>

#include "stvd/imaging/scalar_image.hpp"
#include "stvd/system/interrupter.hpp"
#include "stvd/voxel_grid/grid_geometry.hpp"

namespace stvd::imaging {

/// The voxel grid of an image file (NIfTI, NRRD, MRtrix), from its header:
/// the header is screened as every image header is (docs/reliability.md),
/// but no data are read and a compressed file is decompressed only as far
/// as its header. What the user should know about the header (an Analyze
/// header's orientation) is added to `warnings` when given. Throws
/// ImageIoError naming the file.
GridGeometry readImageGrid(const std::string& path, std::vector<std::string>* warnings = nullptr);

/// Throws ImageIoError(path, "<subject> on another grid than
/// <referenceName> (<mismatch>)") unless the grid of the header of `path`
/// is `reference` (geometryMismatch), before any data are read; `subject`
/// is e.g. "the mask is".
void requireImageOnGrid(const std::string& path, const GridGeometry& reference, const std::string& subject,
                        const std::string& referenceName);

/// readScalarImage and readLabelImage of a side input, after
/// requireImageOnGrid: an image on another grid is refused from its header.
ScalarImage readScalarImageOnGrid(const std::string& path, const GridGeometry& reference,
                                  const std::string& subject, const std::string& referenceName,
                                  Interrupter* interrupter = nullptr);
LabelImage readLabelImageOnGrid(const std::string& path, const GridGeometry& reference, const std::string& subject,
                                const std::string& referenceName, Interrupter* interrupter = nullptr);

}  // namespace stvd::imaging
