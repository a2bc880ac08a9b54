// Private helpers shared by the ITK readers and writers. Includes ITK
// headers: only .cpp files of the adapter include this.
#pragma once

#include <itkImageIOBase.h>

#include <string>
#include <vector>

#include "stvd/grid_geometry.hpp"

namespace stvd::imaging::detail {

/// Registers the NRRD and NIfTI IO factories once per process.
void registerImageIoFactories();

/// One line from an ITK exception: its description with the source
/// locations and line breaks taken out.
std::string conciseItkMessage(const std::exception& e);

/// Opens `path`, picks the ITK reader for it and reads its header. Throws
/// ImageIoError: missing or unreadable file, unknown format, bad header.
itk::ImageIOBase::Pointer openImageForReading(const std::string& path);

/// The geometry of the first three axes, in LPS as ITK reports it. A 2D
/// image gets a third axis of size 1. Throws ImageIoError when the geometry
/// is unusable (e.g. degenerate direction cosines).
GridGeometry geometryOf(itk::ImageIOBase& io, const std::string& path);

/// Reads every component of every pixel, converted to float, in file order
/// (components fastest, then i, j, k, further axes). Throws ImageIoError
/// for truncated or unreadable data.
std::vector<float> readAllComponents(itk::ImageIOBase& io, const std::string& path);

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
