// Scalar images (masks, FA maps, seed labels, distance maps) read and
// written through ITK, held in an ITK-free struct.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "stvd/system/files/output_transaction.hpp"
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

/// Reads a 3D scalar image of any numeric component type (converted to
/// float; a 4D file with one volume is accepted): NIfTI and NRRD through
/// ITK, MRtrix images (.mif, .mif.gz, .mih) through mrtrix_image.hpp. NaN
/// and infinite values stay what they are in every format. A non-zero value
/// stays non-zero. The header is checked before the file's data are read
/// (see docs/reliability.md). Throws ImageIoError naming the file when it is
/// unreadable, truncated, hostile or not a scalar image.
ScalarImage readScalarImage(const std::string& path);

/// A 3D image of integer labels (regions, seed or target labels), read
/// without a detour through float: labels 16777216 and 16777217 stay two
/// labels.
struct LabelImage {
  GridGeometry geometry;
  /// One label per voxel, linear order i + nx*(j + ny*k); 0 = no label.
  std::vector<std::int64_t> labels;
  std::vector<std::string> warnings;
};

/// Reads a 3D label image. Integer component types are taken exactly
/// (unsigned 64-bit values above 2^63 - 1 are refused). A floating-point
/// file must hold integers of magnitude at most 2^53 (NaN counts as 0, no
/// label); another value is refused with the voxel and value named. Throws
/// ImageIoError naming the file.
LabelImage readLabelImage(const std::string& path);

/// Writes a float32 scalar image with exactly this geometry, atomically: the
/// file appears under `path` complete or not at all, and a file that was
/// there stays as it was when writing fails. The format follows the
/// extension (.nii, .nii.gz, .nrrd, .nhdr, .mif, .mif.gz); NRRD data are
/// gzip-compressed (a .nhdr header's data file is "<base>.raw.gz"). What was
/// written is checked before it is moved into place (the file's size for
/// NIfTI, whose writer does not report a full disk; a read-back for NRRD and
/// MRtrix). Refuses to replace an unrelated "<base>.raw.gz"
/// (checkImageOutputCompanions).
/// Throws ImageIoError naming the file.
void writeScalarImage(const std::string& path, const GridGeometry& geometry,
                      const std::vector<float>& values);

/// The same as one output of `outputs`, which moves it into place with the
/// run's other outputs at its commit. Throws files::OutputError.
void writeScalarImage(files::OutputTransaction& outputs, const std::string& path, const GridGeometry& geometry,
                      const std::vector<float>& values);

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
