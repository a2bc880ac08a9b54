// Scalar images (masks, FA maps, seed labels, distance maps) read and
// written through ITK, held in an ITK-free struct.
#pragma once

#include <string>
#include <vector>

#include "stvd/files/output_transaction.hpp"
#include "stvd/grid_geometry.hpp"

namespace stvd::imaging {

/// A 3D scalar image: geometry in LPS millimetres as ITK reports it, one
/// value per voxel in linear order i + nx*(j + ny*k).
struct ScalarImage {
  GridGeometry geometry;
  std::vector<float> values;
};

/// Reads a 3D scalar image of any numeric component type (converted to
/// float; a 4D file with one volume is accepted). Throws ImageIoError
/// naming the file when it is unreadable, truncated or not a scalar image.
ScalarImage readScalarImage(const std::string& path);

/// Writes a float32 scalar image with exactly this geometry, atomically: the
/// file appears under `path` complete or not at all, and a file that was
/// there stays as it was when writing fails. The format follows the
/// extension (.nii, .nii.gz, .nrrd, .nhdr); NRRD data are gzip-compressed
/// (a .nhdr header's data file is "<base>.raw.gz"). What was written is
/// checked before it is moved into place (the file's size for NIfTI, whose
/// writer does not report a full disk; a read-back for NRRD). Refuses to
/// replace an unrelated "<base>.raw.gz" (checkImageOutputCompanions).
/// Throws ImageIoError naming the file.
void writeScalarImage(const std::string& path, const GridGeometry& geometry,
                      const std::vector<float>& values);

/// The same as one output of `outputs`, which moves it into place with the
/// run's other outputs at its commit. Throws files::OutputError.
void writeScalarImage(files::OutputTransaction& outputs, const std::string& path, const GridGeometry& geometry,
                      const std::vector<float>& values);

/// True when the path ends in an image extension stvd reads and writes:
/// .nii, .nii.gz, .nrrd or .nhdr (any letter case).
bool hasImageExtension(const std::string& path);

/// Empty when two geometries describe the same voxel grid: equal sizes,
/// spacings equal to within 1e-4 relative, origins within 1e-3 voxel
/// spacings, direction cosines within 1e-4 (tolerances that absorb the
/// single-precision storage of NIfTI headers). Otherwise a description of
/// the first difference, e.g. "size 112x112x32 differs from 64x64x32".
std::string geometryMismatch(const GridGeometry& a, const GridGeometry& b);

}  // namespace stvd::imaging
