// Images written through ITK, checked afterwards where the library
// underneath does not report a failed write. Private to the ITK file I/O;
// the atomic writing itself is stvd/imaging/detail/image_output.hpp.
#pragma once

#include <functional>
#include <string>
#include <vector>

namespace stvd::imaging::detail {

/// Throws ImageIoError naming `reportedPath` when the image ITK has just
/// written at `path` is not complete, `components` being every value
/// written, in ITK's order.
/// - NIfTI (.nii, .nii.gz): niftilib reports a short write on stderr only
///   and ITK does not throw, so the (decompressed) file must hold the
///   header's vox_offset plus every value, and a gzip stream must end with
///   its trailer (zlib checks the length and CRC).
/// - NRRD (.nrrd, .nhdr): the file is read back through ITK (a detached
///   header with its data file) and compared with `components` bit for bit,
///   which also covers a header cut short.
/// - MRtrix (.mif, .mif.gz): read back by our own reader and compared bit
///   for bit (the writer checks its stream, but a read-back also catches a
///   header and data that disagree).
void checkWrittenImage(const std::string& path, const std::string& reportedPath,
                       const std::vector<float>& components);

}  // namespace stvd::imaging::detail
