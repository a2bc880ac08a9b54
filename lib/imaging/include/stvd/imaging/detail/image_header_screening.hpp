// Our own reading of NIfTI-1, NIfTI-2 and NRRD headers, done before ITK (and
// the niftilib and NrrdIO inside it) sees a file. ITK trusts its headers: a
// non-finite sform makes VNL's SVD spin or abort, a size claim makes NrrdIO
// allocate and zero-fill gigabytes before it finds the file short, an ascii
// token longer than about 1 KB overflows a stack buffer in NrrdIO, a
// `data file:` naming a device is read forever. Every such header is refused
// here with one line naming the file. Free of ITK headers.
#pragma once

#include <array>
#include <cstdint>
#include <string>
#include <vector>

namespace stvd::imaging::detail {

/// Largest magnitude accepted for an affine entry, origin or spacing, in
/// millimetres (1 km): far beyond any scanner, small enough that positions
/// keep sub-micrometre precision in double arithmetic.
constexpr double kMaxCoordinateMm = 1e6;
/// Longest number token accepted in ascii NRRD data (NrrdIO reads tokens
/// into a fixed buffer of about 1 KB).
constexpr std::size_t kMaxAsciiTokenLength = 64;
/// Most header bytes read for NIfTI extensions or NRRD header lines.
constexpr std::size_t kMaxNrrdHeaderBytes = 1 << 20;
/// Longest NRRD field line accepted (but for "content" and "data file"):
/// NrrdIO formats a value it cannot parse into an error message of about
/// 1 KB on the stack, and a line of 1,000 bytes overflows it (SIGABRT).
/// Real fields are far shorter: 16 space directions at full precision take
/// about 400 bytes.
constexpr std::size_t kMaxNrrdFieldLineLength = 512;
/// Deflate cannot expand more than about 1032 to 1: a gzip stream that is
/// claimed to hold more is refused before anything is decompressed.
constexpr double kMaxDeflateRatio = 1032.0;

enum class ImageFileFormat { Nifti, Nrrd };

struct ScreenedImage {
  ImageFileFormat format = ImageFileFormat::Nifti;
  /// NIfTI: 1 or 2, or 0 for an Analyze 7.5 header (no NIfTI magic).
  int niftiVersion = 0;
  /// The header exactly as stored (348 or 540 bytes; NIfTI only), and the
  /// file that holds the voxel data (the .img of a pair).
  std::vector<unsigned char> niftiHeader;
  std::string dataPath;
  bool niftiSwapped = false;  ///< header in the other byte order than this machine's
  /// NIfTI dim[0..7] as stored (dim[0] = number of dimensions).
  std::array<std::int64_t, 8> niftiDim{};
  std::int64_t niftiDatatype = 0;
  std::uint64_t dataOffset = 0;     ///< NIfTI vox_offset
  std::uint64_t elementCount = 0;   ///< values in the file (all axes, all components)
  unsigned elementBytes = 0;        ///< bytes of one stored value
  bool gzipData = false;            ///< the data are a gzip stream (.nii.gz, NRRD gzip)
  /// Things worth telling the user about a readable file, in our words.
  std::vector<std::string> warnings;
};

/// Reads and checks the header of an image file, and the size of its data,
/// before any library parses it. The format follows the name: .nii,
/// .nii.gz, .hdr/.img (NIfTI-1 pair or Analyze 7.5) or .nrrd/.nhdr. Throws
/// ImageIoError with one line naming the file: unknown extension, damaged
/// header, sizes out of range or beyond what the file (or its gzip stream)
/// holds or the machine's memory, non-finite or absurd geometry (beyond
/// kMaxCoordinateMm), ascii tokens beyond kMaxAsciiTokenLength, a data file
/// that is not a regular file, skips beyond the data file. With `withData`
/// false, the header alone: its fields are checked (sizes, geometry), but
/// not what the data need (memory, the file's or the gzip stream's
/// length, ascii tokens): enough for ITK to read the header, as a side
/// input's grid is compared with the tensors' before its data are touched.
ScreenedImage screenImageFile(const std::string& path, bool withData = true);

/// The checks every image reader applies to what a header declares, also
/// used by the MRtrix reader (mrtrix_image.cpp), which reads its headers
/// itself. Each throws ImageIoError naming `reportedPath`.
///
/// The size of a regular file, after following symbolic links; a device or
/// a FIFO (which can be read from forever) is refused. `role` names the
/// file in the message ("the data file").
std::uint64_t regularFileSize(const std::string& path, const std::string& reportedPath, const std::string& role);
/// `elements` stored values of `elementBytes` each, and their
/// single-precision copy, must fit in the memory available (system,
/// control group, ulimit -v).
void checkValuesFitInMemory(std::uint64_t elements, unsigned elementBytes, const std::string& reportedPath);
/// A coordinate, spacing or affine entry must be finite and at most
/// kMaxCoordinateMm in magnitude; `what` names it in the message.
void checkCoordinate(double x, const std::string& what, const std::string& reportedPath);

/// A value of the file that is NaN or infinite, and where it is (file
/// order, all axes).
struct NonFiniteValue {
  std::uint64_t index;
  double value;
};

/// The NIfTI data values that are NaN or infinite, for float32 and float64
/// data; empty for other types. niftilib replaces such values by 0 on
/// reading, which would turn a missing tensor into a zero one and an
/// infinite label into no label; the reader puts them back. Throws
/// ImageIoError.
std::vector<NonFiniteValue> nonFiniteNiftiValues(const ScreenedImage& image, const std::string& path);

/// A NIfTI header with the same geometry fields as `image` but three
/// dimensions (dim = 3, nx, ny, nz) and no intent: ITK reads the geometry of
/// a 5D tensor file of one slice from it, since for those it drops the
/// singleton third axis together with its spacing and origin.
std::vector<unsigned char> threeDimensionalNiftiHeader(const ScreenedImage& image);

}  // namespace stvd::imaging::detail
