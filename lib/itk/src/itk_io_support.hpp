// Private helpers shared by the ITK readers and writers. Includes ITK
// headers: only .cpp files of the adapter include this.
#pragma once

#include <itkImageIOBase.h>

#include <string>
#include <vector>

#include "stvd/imaging/detail/image_header_screening.hpp"
#include "stvd/voxel_grid/grid_geometry.hpp"

namespace stvd::imaging::detail {

/// Registers the NRRD and NIfTI IO factories once per process.
void registerImageIoFactories();

/// One line from an ITK exception: its description with the source
/// locations and line breaks taken out.
std::string conciseItkMessage(const std::exception& e);

/// An image file opened for reading: ITK's reader with the header read, and
/// what our own screening of the header found.
struct OpenedImage {
  itk::ImageIOBase::Pointer io;
  ScreenedImage screened;
  bool isNifti() const { return screened.format == ImageFileFormat::Nifti; }
};

/// Screens the header (image_header_screening.hpp), then opens `path` with
/// the ITK reader for it and reads the header. Throws ImageIoError: missing
/// or unreadable file (or not a regular file), unknown format, bad or
/// hostile header. With `withData` false the screening leaves out what only
/// reading the data needs (screenImageFile): for the grid alone.
OpenedImage openImageForReading(const std::string& path, bool withData = true);

/// The geometry of the first three axes, in LPS as ITK reports it. A 2D
/// image gets a third axis of size 1; a NIfTI file whose third axis ITK
/// dropped (a 5D tensor file of one slice) gets it back from its header.
/// Throws ImageIoError when the geometry is unusable (degenerate direction
/// cosines, an origin beyond kMaxCoordinateMm).
GridGeometry geometryOf(const OpenedImage& image, const std::string& path);

/// Every component of every pixel as stored, in file order (components
/// fastest, then i, j, k, further axes), with the values niftilib turned
/// from NaN or infinity into 0 put back.
struct RawComponents {
  std::vector<char> bytes;
  itk::IOComponentEnum type = itk::IOComponentEnum::UNKNOWNCOMPONENTTYPE;
  std::size_t count = 0;
};
RawComponents readRawComponents(OpenedImage& image, const std::string& path);

/// readRawComponents() converted to float. Throws ImageIoError for
/// truncated or unreadable data.
std::vector<float> readAllComponents(OpenedImage& image, const std::string& path);

/// Prepares an ITK writer for `path` (the format follows the extension):
/// geometry of the first three axes, float32 components. `extraAxis` > 0
/// adds a fourth axis of that size (six-volume NIfTI). Throws ImageIoError
/// for an unsupported extension.
itk::ImageIOBase::Pointer createFloatWriter(const std::string& path, const std::string& reportedPath,
                                            const GridGeometry& geometry, unsigned components,
                                            itk::IOPixelEnum pixelType, unsigned extraAxis = 0);

/// Writes `data` through `io` (prepared by createFloatWriter). Throws
/// ImageIoError naming `reportedPath`.
void writeFloatData(itk::ImageIOBase& io, const std::string& reportedPath, const float* data);

}  // namespace stvd::imaging::detail
