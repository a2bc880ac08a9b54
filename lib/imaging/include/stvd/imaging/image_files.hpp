// The files behind an image path: what reading it opens and what writing it
// creates. A detached NRRD header and an MRtrix .mih header name data files
// of their own, and a NIfTI pair is a header and an image file; an output must be none of an input's
// files (stvd/system/files/file_identity.hpp), and writing an image must not
// replace a file that is not part of it.
#pragma once

#include <string>
#include <vector>

namespace stvd::imaging {

/// The files reading the image at `path` opens: `path` itself, the data
/// files a NRRD header (.nhdr, or a .nrrd with a "data file" field) names,
/// relative to the header's folder, the other half of a NIfTI pair
/// (.hdr: .img and .img.gz; .img, .img.gz: .hdr), and the data file an
/// MRtrix .mih header names. A header that cannot be read adds nothing:
/// reading it fails later, with its own message.
std::vector<std::string> imageFilesRead(const std::string& path);

/// The files writing an image to `path` creates: `path` itself and, for a
/// detached NRRD header "<base>.nhdr", its gzip-compressed data file
/// "<base>.raw.gz" next to it.
std::vector<std::string> imageFilesWritten(const std::string& path);

/// Throws ImageIoError naming the file when writing an image to `path`
/// would replace a file that is not part of the image at `path` now: an
/// existing "<base>.raw.gz" that the existing header "<base>.nhdr" (if any)
/// does not name as its data file. Rewriting a .nhdr that stvd wrote
/// before is fine.
void checkImageOutputCompanions(const std::string& path);

}  // namespace stvd::imaging
