// MRtrix's own image format (.mif, .mif.gz, and .mih with a separate data
// file), read and written by our own code (no ITK, no MRtrix library).
//
// A file starts with the line "mrtrix image", then "key: value" lines up to
// a line "END" (or the end of a .mih file). The keys used here:
//   dim:       sizes of the axes, e.g. 112,112,32,6
//   vox:       voxel sizes in mm (the first three are used)
//   layout:    how the axes are stored, e.g. -0,+1,+2,+3: axis a's entry is
//              its rank in memory (0 fastest) and a sign; '-' stores the
//              axis in reverse order
//   datatype:  Bit, Int8, UInt8, [U]Int16/32/64, Float32, Float64, each
//              wider one with LE or BE (without, the machine's order)
//   transform: three lines, the rows of the 3x4 matrix that takes
//              (i*vox0, j*vox1, k*vox2, 1) to scanner RAS millimetres
//   scaling:   optional "offset,multiplier" applied to the stored values
//   file:      ". OFFSET" (data in this file from byte OFFSET) or
//              "NAME [OFFSET]" (data in NAME, next to a .mih header)
// Other keys (command_history, dw_scheme, comments, ...) are ignored.
//
// Every size a header declares is checked before anything is allocated, by
// the rules of the other image formats (docs/reliability.md, "Inputs"): the
// product of the sizes may not overflow, the grid must fit stvd's 32-bit
// voxel numbers, the data must fit in the file that holds it (a regular
// file: no device or FIFO), and the values in the memory available; voxel
// sizes and transform entries are finite and at most 1e6 mm. For .mif.gz a
// claim beyond deflate's 1032-to-1 ratio fails at once, and otherwise the
// stream is decompressed as far as it goes, never further than the header
// asks, before anything is kept.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

#include "stvd/imaging/tensor_frames.hpp"
#include "stvd/system/interrupter.hpp"
#include "stvd/voxel_grid/grid_geometry.hpp"

namespace stvd::imaging {

/// The header of an MRtrix image, as parsed and checked.
struct MrtrixHeader {
  std::vector<std::size_t> size;       ///< dim, at least 1 axis (2D images get a third of 1)
  std::array<double, 3> spacing{1, 1, 1};
  /// layout: stride of each axis in elements (negative: stored reversed).
  std::vector<long long> strides;
  /// Element offset of voxel (0, 0, ...) from the start of the data.
  std::size_t firstElement = 0;
  std::string datatype;                ///< as written, e.g. "Float32LE"
  int bytesPerElement = 4;             ///< 0 for Bit
  double scalingOffset = 0.0, scalingMultiplier = 1.0;
  /// Rows of the 3x4 scanner transform (RAS).
  std::array<double, 12> transform{1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0};
  std::string dataFile;                ///< "." for data in the header's own file
  std::size_t dataOffset = 0;          ///< byte offset of the data in that file
  std::size_t elementCount() const;    ///< product of the sizes
  std::size_t dataBytes() const;       ///< bytes the data take in the file
};

/// An MRtrix image in memory.
struct MrtrixImage {
  MrtrixHeader header;
  /// The geometry of the first three axes in LPS (stvd's convention): the
  /// transform's translation and columns with x and y negated.
  GridGeometry geometry;
  /// Every value (scaling applied) in logical order: axis 0 fastest, then
  /// axis 1, ... whatever the file's layout. Without scaling a value is
  /// the stored one, bit for bit (NaN and infinity included).
  std::vector<float> values;
};

/// An MRtrix image of integer labels in memory.
struct MrtrixLabelImage {
  MrtrixHeader header;
  GridGeometry geometry;
  /// Every label in logical order: integer datatypes (Bit, [U]Int8-64)
  /// without scaling exactly; other values by the rules of readLabelImage
  /// (stvd/itk/scalar_image_io.hpp): integers of magnitude at most 2^53, NaN as 0.
  std::vector<std::int64_t> labels;
};

/// True when the path ends in .mif, .mif.gz or .mih (any letter case).
bool isMrtrixImagePath(const std::string& path);

/// Parses and checks the header at the start of `bytes` (the whole file or
/// at least its header). The header ends with a line "END", or with the
/// text when `endsWithText` (a .mih file, which MRtrix writes without END).
/// `name` is used in messages. Throws ImageIoError with one line naming
/// `name`.
MrtrixHeader parseMrtrixHeader(std::string_view bytes, const std::string& name, bool endsWithText = false);

/// An image whose header and data are both in `bytes` (a .mif file's
/// content, "file: . OFFSET"), for data already in memory. Throws
/// ImageIoError naming `name`.
MrtrixImage parseMrtrixImage(std::string_view bytes, const std::string& name);

/// Reads a .mif, .mif.gz or .mih file (with its data file). Throws
/// ImageIoError with one line naming the file. `interrupter` hears
/// "reading image": 0 %, 50 % once the file's bytes are read (in one
/// piece), the decoding of its values, 100 %; when it asks to stop,
/// Cancelled is thrown.
MrtrixImage readMrtrixImage(const std::string& path, Interrupter* interrupter = nullptr);

/// The grid of a .mif, .mif.gz or .mih file from its header alone: no data
/// read, a .mif.gz decompressed only as far as its header. Throws
/// ImageIoError naming the file.
GridGeometry readMrtrixImageGrid(const std::string& path);

/// Reads a .mif, .mif.gz or .mih file of labels without a detour through
/// float. Throws ImageIoError with one line naming the file (and the voxel,
/// for a value that is no label). `interrupter`: as for readMrtrixImage
/// ("reading labels").
MrtrixLabelImage readMrtrixLabelImage(const std::string& path, Interrupter* interrupter = nullptr);

/// The file that holds the data of the image at `path`: `path` itself for
/// .mif and .mif.gz, the data file a .mih header names (relative to the
/// header's folder), or "" when the header cannot be read (reading the
/// image then fails with its own message).
std::string mrtrixDataFile(const std::string& path);

/// An MRtrix image's voxel frame: its first three axes in the order and
/// direction they are stored (the layout), in LPS, as columns. An image
/// that mrconvert made from a NIfTI file keeps that file's storage, and
/// components given along the voxel axes (tensors, spherical harmonics)
/// stay in that file's voxel frame whatever axes MRtrix shows; a file stvd
/// writes stores its axes as they are, so the two frames agree.
Matrix3 mrtrixStoredVoxelAxes(const MrtrixHeader& header, const GridGeometry& geometryLps);

/// How MRtrix numbers the voxels of an image. MRtrix reorders the axes of
/// every image it opens (NIfTI, NRRD or its own) so that the first, second
/// and third point as nearly as possible to right, anterior and superior:
/// MRtrix axis r is image axis `axis[r]`, counted backwards when
/// `reversed[r]`. mrview, mrconvert -coord and mrinfo count voxels in that
/// order; stvd counts them as the file stores them.
struct MrtrixAxisOrder {
  std::array<int, 3> axis{0, 1, 2};
  std::array<bool, 3> reversed{false, false, false};
};
MrtrixAxisOrder mrtrixAxisOrder(const GridGeometry& geometryLps);
/// The index MRtrix shows for the voxel stvd calls `index`.
std::array<long, 3> mrtrixVoxelIndex(const GridGeometry& geometryLps, const std::array<long, 3>& index);

/// Writes `values` (volumes of geometry.voxelCount() values each, the
/// first volume first) as float32 .mif, or .mif.gz when `formatPath` ends
/// so, to `path`: axes 0, 1, 2 (and 3 for several volumes) stored in that
/// order, the scanner transform from the LPS geometry. The same values give
/// the same bytes (the gzip stream carries no time stamp). Checks every
/// write, not what was written: callers read the file back
/// (written_files.hpp). Throws ImageIoError naming `formatPath`.
void writeMrtrixImage(const std::string& path, const std::string& formatPath, const GridGeometry& geometry,
                      const std::vector<float>& values, std::size_t volumes = 1);

}  // namespace stvd::imaging
