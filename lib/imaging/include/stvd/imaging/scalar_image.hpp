// Scalar images (masks, FA maps, seed labels, distance maps) in memory, and
// how their grids are compared. Reading and writing them: stvd/itk/
// scalar_image_io.hpp (NIfTI and NRRD through ITK, MRtrix through
// mrtrix_image.hpp).
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "stvd/voxel_grid/grid_geometry.hpp"

namespace stvd::imaging {

/// A 3D scalar image: geometry in LPS millimetres as ITK reports it, one
/// value per voxel in linear order i + nx*(j + ny*k).
struct ScalarImage {
  GridGeometry geometry;
  std::vector<float> values;
  /// What the user should know about a file that was read all the same.
  std::vector<std::string> warnings;
};

/// A 3D image of integer labels (regions, seed or target labels), read
/// without a detour through float: labels 16777216 and 16777217 stay two
/// labels.
struct LabelImage {
  GridGeometry geometry;
  /// One label per voxel, linear order i + nx*(j + ny*k); 0 = no label.
  std::vector<std::int64_t> labels;
  std::vector<std::string> warnings;
};

/// True when the path ends in an image extension stvd reads and writes:
/// .nii, .nii.gz, .nrrd, .nhdr, .mif or .mif.gz (any letter case).
bool hasImageExtension(const std::string& path);

/// Empty when two geometries describe the same voxel grid: equal sizes,
/// spacings equal to within 1e-4 relative, origins within 1e-3 voxel
/// spacings, direction cosines within 1e-4 (tolerances that absorb the
/// single-precision storage of NIfTI headers). Otherwise a description of
/// the first difference, e.g. "size 112x112x32 differs from 64x64x32".
std::string geometryMismatch(const GridGeometry& a, const GridGeometry& b);

/// Throws ImageIoError(imageName, "<subject> on another grid than
/// <referenceName> (<mismatch>)") unless geometryMismatch(image, reference)
/// is empty; `subject` is e.g. "the mask is" or "the seed labels are".
void requireSameGrid(const GridGeometry& image, const GridGeometry& reference, const std::string& imageName,
                     const std::string& subject, const std::string& referenceName);

}  // namespace stvd::imaging
