// Scalar images (masks, FA maps, seed labels, distance maps) read and
// written as files: NIfTI and NRRD through ITK, MRtrix images through our own
// code (stvd/imaging/mrtrix_image.hpp), each checked before and after.
#pragma once

#include <string>
#include <vector>

#include "stvd/imaging/scalar_image.hpp"
#include "stvd/system/files/output_transaction.hpp"
#include "stvd/system/interrupter.hpp"
#include "stvd/voxel_grid/grid_geometry.hpp"

namespace stvd::imaging {

/// Reads a 3D scalar image of any numeric component type (converted to
/// float; a 4D file with one volume is accepted): NIfTI and NRRD through
/// ITK, MRtrix images (.mif, .mif.gz, .mih) through mrtrix_image.hpp. NaN
/// and infinite values stay what they are in every format. A non-zero value
/// stays non-zero. The header is checked before the file's data are read
/// (see docs/reliability.md). Throws ImageIoError naming the file when it is
/// unreadable, truncated, hostile or not a scalar image.
///
/// `interrupter` hears "reading image": 0 %, 100 %, and for an MRtrix
/// image 50 % once its bytes are read and the decoding of its values in
/// between; ITK's read of a NIfTI or NRRD file and the conversion of its
/// values to float are one piece that cannot be cut. When it asks to stop,
/// Cancelled is thrown.
ScalarImage readScalarImage(const std::string& path, Interrupter* interrupter = nullptr);

/// Reads a 3D label image. Integer component types are taken exactly
/// (unsigned 64-bit values above 2^63 - 1 are refused). A floating-point
/// file must hold integers of magnitude at most 2^53 (NaN counts as 0, no
/// label); another value is refused with the voxel and value named. Throws
/// ImageIoError naming the file. `interrupter` hears "reading labels": 0 %,
/// 50 % once the values are read (ITK's read in one piece), their
/// conversion into labels, 100 %; when it asks to stop, Cancelled is
/// thrown.
LabelImage readLabelImage(const std::string& path, Interrupter* interrupter = nullptr);

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

}  // namespace stvd::imaging
